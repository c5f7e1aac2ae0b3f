#pragma once
// The report's figures drawn from its data: the per-image plots in capture order (focal length,
// distortion, principal point, reprojection error, point count), the histograms, the match
// matrix and the stage times, each an inline SVG string (empty when there is nothing to draw).
#include <string>
#include <vector>

#include "varsfm/report/report_data.h"

namespace varsfm {

struct ReportCharts {
  std::string focal;
  std::string focal_colorbar;
  std::string k1, k2;
  std::string principal_u, principal_v;
  std::string error_per_image, points_per_image;
  std::string error_histogram, track_histogram;
  std::string match_matrix;
  std::string stage_times, mapping_times;
};

// Whether the registered images share one size, so that their focal lengths in pixels compare
// as zoom factors. Photos of several sizes (two phones, a resized copy) compare by the focal
// length over the longer image side instead: in pixels it follows the photo's size, not the zoom.
bool FocalLengthsInPixels(const ReportData& data);

// The focal length the report's colours, plot and "relative" figures compare: in pixels when
// `in_pixels` (FocalLengthsInPixels), else over the image's longer side.
double ComparableFocal(const Camera& camera, bool in_pixels);

// The colour of each image (ReportData::images order) on the focal-length scale (FocalScale);
// empty for images not in the model.
std::vector<std::string> FocalColors(const ReportData& data);

// The shortest and longest comparable focal length (ComparableFocal) of the registered images
// (0, 0 when none).
std::pair<double, double> FocalRange(const ReportData& data);

// The focal lengths the colour scale (and the focal plot's axis, at least) spans: FocalRange,
// widened to 2 % of the focal length around its middle, so that the estimation noise of a
// fixed zoom (fountain-P11: 0.1 %) shows as one colour and a flat line rather than as a zoom.
std::pair<double, double> FocalScale(const ReportData& data);

ReportCharts DrawReportCharts(const ReportData& data);

}  // namespace varsfm
