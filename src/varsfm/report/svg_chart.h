#pragma once
// The report's charts as inline SVG, drawn here rather than by a charting library so the page
// needs nothing beside it. Every mark carries a <title> (the browser's tooltip) with its exact
// value; per-image marks carry data-image="<image id>" so the page can link them to the 3D view.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "varsfm/util/types.h"

namespace varsfm {

struct ChartFrame {
  int width = 560;
  int height = 240;
  std::string title;
  std::string x_label;
  std::string y_label;
};

// One value per image, in capture order: markers joined by a line, or bars.
struct PerImageSeries {
  std::vector<image_t> image_ids;
  std::vector<std::string> names;             // x labels and tooltips
  std::vector<std::optional<double>> values;  // nothing: the image is not in the model
  std::vector<std::string> colors;            // per marker; empty: `color` for all
  std::string color = "#3b528b";
  bool bars = false;                // bars from zero instead of a line
  std::optional<double> reference;  // a dashed horizontal line (e.g. 0, the image centre)
  std::string reference_label;
  // A second axis on the right showing value / right_axis_unit as "x1.25": the focal length
  // relative to the shortest one.
  std::optional<double> right_axis_unit;
  std::optional<std::pair<double, double>> min_range;  // the axis covers at least this
  int decimals = 2;                                    // of the values in tooltips
};

std::string PerImageChartSvg(const ChartFrame& frame, const PerImageSeries& series);

// A histogram in `num_bins` equal bins over [0, upper]; values above are counted in the last
// bin, which is then labelled "+". `integers`: one bin per whole number 0 .. upper - 1 (track
// lengths), labelled at its centre.
struct Histogram {
  std::vector<double> values;
  int num_bins = 20;
  double upper = 1;
  bool integers = false;
  std::string color = "#21918c";
};
std::string HistogramSvg(const ChartFrame& frame, const Histogram& histogram);

// The pair-match matrix: cell (i, j) coloured by the inlier count of images i and j (log scale),
// faint where the pair has fewer than `min_inliers`. Above `max_cells` images per side the
// images are grouped into blocks and a cell shows the block's strongest pair.
struct MatchMatrix {
  std::vector<image_t> image_ids;
  std::vector<std::string> names;
  std::vector<std::pair<std::pair<size_t, size_t>, size_t>> cells;  // (row, col) indices, inliers
  size_t min_inliers = 15;
};
std::string MatchMatrixSvg(const MatchMatrix& matrix, int size = 480, size_t max_cells = 150);

// One horizontal stacked bar of named durations (seconds), with a legend.
std::string StageTimesSvg(const std::vector<std::pair<std::string, double>>& stages,
                          int width = 900);

// A horizontal colour bar from `low` to `high` (viridis), labelled, for the focal-length scale;
// its ends are written with `decimals` decimals.
std::string ColorBarSvg(double low, double high, const std::string& label, int decimals = 0,
                        int width = 220);

// Tick positions from `low` to `high` at a step of 1, 2 or 5 times a power of ten, about
// `target` of them, covering the interval (the first <= low, the last >= high).
std::vector<double> NiceTicks(double low, double high, int target = 5);

}  // namespace varsfm
