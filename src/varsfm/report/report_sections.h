#pragma once
// The HTML of the report's sections, each a <section> element.
#include <optional>
#include <string>

#include "varsfm/report/report_charts.h"
#include "varsfm/report/report_data.h"
#include "varsfm/report/three_js.h"

namespace varsfm {

// Images in, registered, model, points, observations, errors, initial pair, later stages, time.
std::string SummarySection(const ReportData& data, const ReportCharts& charts);

// The 3D view (or why it is missing) beside the focal-length plot and its colour scale.
std::string OverviewSection(const ReportData& data, const ReportCharts& charts,
                            const std::optional<ThreeJs>& three);

// Distortion, principal point, reprojection error, points per image, histograms, match matrix.
std::string FiguresSection(const ReportCharts& charts);

// The textured model rendered from the registered cameras and compared with the photos
// (summary.json's "renders", written by `run --holdout N`): held-out and source views' means and
// one row per image. Empty when the run scored no renders.
std::string RendersSection(const ReportData& data);

// One row per image with its thumbnail and figures; unregistered images with the reason.
std::string ImagesSection(const ReportData& data);

}  // namespace varsfm
