#include "varsfm/report/report_charts.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <string>
#include <utility>

#include "varsfm/report/colormap.h"
#include "varsfm/report/svg_chart.h"
#include "varsfm/util/statistics.h"

namespace varsfm {
namespace {

// A per-image series of `value` over the registered images (nothing for the others).
PerImageSeries SeriesOf(const ReportData& data,
                        const std::function<std::optional<double>(const ReportImage&)>& value) {
  PerImageSeries series;
  for (const ReportImage& image : data.images) {
    series.image_ids.push_back(image.image_id);
    series.names.push_back(image.name);
    series.values.push_back(image.registered ? value(image) : std::nullopt);
  }
  return series;
}

// The frame of the small per-image charts: the images along x, in capture order.
ChartFrame SmallImageFrame(int height, std::string title, std::string y_label) {
  return {.width = 440,
          .height = height,
          .title = std::move(title),
          .x_label = "image",
          .y_label = std::move(y_label)};
}

void DrawIntrinsics(const ReportData& data, ReportCharts* charts) {
  const double shortest = FocalRange(data).first;
  const auto [low, high] = FocalScale(data);
  const bool in_pixels = FocalLengthsInPixels(data);
  PerImageSeries focal =
      SeriesOf(data, [&](const ReportImage& i) { return ComparableFocal(i.camera, in_pixels); });
  focal.colors = FocalColors(data);
  focal.color = "#555";
  focal.right_axis_unit = shortest;
  focal.min_range = {low, high};
  focal.decimals = in_pixels ? 1 : 3;
  const std::string unit = in_pixels ? "focal length (px)" : "focal length / longer image side";
  charts->focal = PerImageChartSvg({.width = 620,
                                    .height = 300,
                                    .title = "Focal length per image (capture order)",
                                    .x_label = "image",
                                    .y_label = unit},
                                   focal);
  if (high > 0) charts->focal_colorbar = ColorBarSvg(low, high, unit, in_pixels ? 0 : 3);

  PerImageSeries k1 =
      SeriesOf(data, [](const ReportImage& i) { return i.camera.params[Camera::kK1]; });
  k1.reference = 0.0;
  k1.decimals = 4;
  charts->k1 = PerImageChartSvg(SmallImageFrame(200, "Radial distortion k1", "k1"), k1);
  PerImageSeries k2 =
      SeriesOf(data, [](const ReportImage& i) { return i.camera.params[Camera::kK2]; });
  k2.reference = 0.0;
  k2.decimals = 4;
  k2.color = "#21918c";
  charts->k2 = PerImageChartSvg(SmallImageFrame(200, "Radial distortion k2", "k2"), k2);
  PerImageSeries u = SeriesOf(data, [](const ReportImage& i) {
    return i.camera.params[Camera::kU0] - i.camera.width / 2.0;
  });
  u.reference = 0.0;
  u.reference_label = "image centre";
  charts->principal_u =
      PerImageChartSvg(SmallImageFrame(200, "Principal point u0 \u2212 width/2", "px"), u);
  PerImageSeries v = SeriesOf(data, [](const ReportImage& i) {
    return i.camera.params[Camera::kV0] - i.camera.height / 2.0;
  });
  v.reference = 0.0;
  v.reference_label = "image centre";
  v.color = "#21918c";
  charts->principal_v =
      PerImageChartSvg(SmallImageFrame(200, "Principal point v0 \u2212 height/2", "px"), v);
}

void DrawFit(const ReportData& data, ReportCharts* charts) {
  PerImageSeries error = SeriesOf(data, [](const ReportImage& i) { return i.rms_error_px; });
  error.bars = true;
  error.decimals = 3;
  error.color = "#3b528b";
  charts->error_per_image =
      PerImageChartSvg(SmallImageFrame(220, "RMS reprojection error per image", "px"), error);
  PerImageSeries points =
      SeriesOf(data, [](const ReportImage& i) { return static_cast<double>(i.num_points3D); });
  points.bars = true;
  points.decimals = 0;
  points.color = "#21918c";
  charts->points_per_image =
      PerImageChartSvg(SmallImageFrame(220, "3D points seen per image", "observations"), points);
  if (!data.observation_errors_px.empty()) {
    // Up to the 99th percentile: a few large errors would squeeze the rest into one bin.
    const double upper = std::max(1e-3, Quantile(data.observation_errors_px, 0.99));
    charts->error_histogram = HistogramSvg({.width = 440,
                                            .height = 220,
                                            .title = "Reprojection error of every observation",
                                            .x_label = "px",
                                            .y_label = "observations"},
                                           {.values = data.observation_errors_px,
                                            .num_bins = 30,
                                            .upper = upper,
                                            .integers = false,
                                            .color = "#3b528b"});
  }
  if (!data.track_lengths.empty()) {
    std::vector<double> lengths(data.track_lengths.begin(), data.track_lengths.end());
    const double longest = std::min(40.0, Quantile(lengths, 1.0));
    charts->track_histogram = HistogramSvg(
        {.width = 440,
         .height = 220,
         .title = "Track length",
         .x_label = "images per 3D point",
         .y_label = "3D points"},
        {.values = lengths, .upper = longest + 1, .integers = true, .color = "#21918c"});
  }
}

void DrawWorkspace(const ReportData& data, ReportCharts* charts) {
  MatchMatrix matrix;
  matrix.min_inliers = data.min_pair_inliers;
  std::map<image_t, size_t> index;
  for (const ReportImage& image : data.images) {
    if (image.image_id == kInvalidImageId) continue;
    index[image.image_id] = matrix.image_ids.size();
    matrix.image_ids.push_back(image.image_id);
    matrix.names.push_back(image.name);
  }
  for (const WorkspacePairRow& pair : data.pairs) {
    const auto a = index.find(pair.image_id1), b = index.find(pair.image_id2);
    if (a == index.end() || b == index.end()) continue;
    matrix.cells.push_back({{a->second, b->second}, pair.num_inliers});
  }
  if (!matrix.cells.empty()) charts->match_matrix = MatchMatrixSvg(matrix);

  const nlohmann::json seconds = data.summary.value("seconds", nlohmann::json::object());
  const auto stages = [&](const std::vector<std::pair<std::string, std::string>>& keys) {
    std::vector<std::pair<std::string, double>> out;
    for (const auto& [key, label] : keys)
      if (seconds.contains(key) && seconds[key].is_number()) out.push_back({label, seconds[key]});
    return out;
  };
  charts->stage_times = StageTimesSvg(stages({{"extract", "extract"},
                                              {"match", "match"},
                                              {"map", "map"},
                                              {"densify", "densify"},
                                              {"mesh", "mesh"},
                                              {"texture", "texture"}}));
  charts->mapping_times = StageTimesSvg(stages({{"initialization", "initial pair"},
                                                {"registration", "registration"},
                                                {"triangulation", "triangulation"},
                                                {"local_ba", "local BA"},
                                                {"global_ba", "global BA"}}));
}

}  // namespace

bool FocalLengthsInPixels(const ReportData& data) {
  const ReportImage* first = nullptr;
  for (const ReportImage& image : data.images) {
    if (!image.registered) continue;
    if (!first) first = &image;
    if (image.camera.width != first->camera.width || image.camera.height != first->camera.height)
      return false;
  }
  return true;
}

double ComparableFocal(const Camera& camera, bool in_pixels) {
  const int longer_side = std::max(camera.width, camera.height);
  return in_pixels || longer_side <= 0 ? camera.focal() : camera.focal() / longer_side;
}

std::pair<double, double> FocalRange(const ReportData& data) {
  const bool in_pixels = FocalLengthsInPixels(data);
  double shortest = INFINITY, longest = 0;
  for (const ReportImage& image : data.images) {
    if (!image.registered) continue;
    shortest = std::min(shortest, ComparableFocal(image.camera, in_pixels));
    longest = std::max(longest, ComparableFocal(image.camera, in_pixels));
  }
  if (longest == 0) return {0, 0};
  return {shortest, longest};
}

std::pair<double, double> FocalScale(const ReportData& data) {
  const auto [shortest, longest] = FocalRange(data);
  const double middle = (shortest + longest) / 2,
               half = std::max(longest - shortest, 0.02 * middle) / 2;
  return {middle - half, middle + half};
}

std::vector<std::string> FocalColors(const ReportData& data) {
  const auto [low, high] = FocalScale(data);
  const bool in_pixels = FocalLengthsInPixels(data);
  std::vector<std::string> colors;
  for (const ReportImage& image : data.images) {
    if (!image.registered) {
      colors.emplace_back();
      continue;
    }
    const double focal = ComparableFocal(image.camera, in_pixels);
    colors.push_back(ViridisHex(high > low ? (focal - low) / (high - low) : 0.5));
  }
  return colors;
}

ReportCharts DrawReportCharts(const ReportData& data) {
  ReportCharts charts;
  DrawIntrinsics(data, &charts);
  DrawFit(data, &charts);
  DrawWorkspace(data, &charts);
  return charts;
}

}  // namespace varsfm
