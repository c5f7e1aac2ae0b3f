// The charts of svg_chart.h that are not plots on axes: the match matrix, the stage-time bar
// and the colour bar.
#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "varsfm/report/colormap.h"
#include "varsfm/report/html_text.h"
#include "varsfm/report/svg_chart.h"

namespace varsfm {

std::string MatchMatrixSvg(const MatchMatrix& matrix, int size, size_t max_cells) {
  const size_t n = matrix.image_ids.size();
  if (n == 0) return "";
  // Images per block: 1 unless there are more than max_cells images.
  const size_t group = (n + max_cells - 1) / max_cells;
  const size_t blocks = (n + group - 1) / group;
  const int margin = blocks <= 40 ? 36 : 12;
  const double cell = static_cast<double>(size - margin) / blocks;
  size_t most = 1;
  // Strongest pair per block (row < col kept; drawn on both sides of the diagonal).
  std::map<std::pair<size_t, size_t>, std::pair<size_t, std::pair<size_t, size_t>>> strongest;
  for (const auto& [rc, inliers] : matrix.cells) {
    const size_t a = std::min(rc.first, rc.second), b = std::max(rc.first, rc.second);
    auto& best = strongest[{a / group, b / group}];
    if (inliers >= best.first) best = {inliers, {a, b}};
    most = std::max(most, inliers);
  }
  std::string svg = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"chart matrix\" width=\"{0}\" "
      "height=\"{0}\" viewBox=\"0 0 {0} {0}\"><rect x=\"{1}\" y=\"{1}\" width=\"{2:.1f}\" "
      "height=\"{2:.1f}\" class=\"matrix-bg\"/>",
      size, margin, cell * blocks);
  const double log_most = std::log1p(static_cast<double>(most));
  for (const auto& [block, best] : strongest) {
    const auto [inliers, pair] = best;
    const std::string color = ViridisHex(std::log1p(static_cast<double>(inliers)) / log_most);
    const std::string faint = inliers < matrix.min_inliers ? " opacity=\"0.35\"" : "";
    const std::string title =
        fmt::format("{}{} \u2013 {}: {} inliers{}", group > 1 ? "strongest in block: " : "",
                    EscapeHtml(matrix.names[pair.first]), EscapeHtml(matrix.names[pair.second]),
                    inliers, inliers < matrix.min_inliers ? " (too few: not used)" : "");
    for (const auto& [r, c] : {block, std::pair{block.second, block.first}}) {
      svg += fmt::format(
          "<rect x=\"{:.2f}\" y=\"{:.2f}\" width=\"{:.2f}\" height=\"{:.2f}\" fill=\"{}\"{}>"
          "<title>{}</title></rect>",
          margin + c * cell, margin + r * cell, cell, cell, color, faint, title);
    }
  }
  if (blocks <= 40) {  // image numbers along both axes
    for (size_t i = 0; i < blocks; ++i) {
      const double at = margin + (i + 0.5) * cell;
      const std::string name = EscapeHtml(matrix.names[i]);
      svg += fmt::format(
          "<text class=\"tick\" x=\"{:.1f}\" y=\"{}\" text-anchor=\"middle\">{}<title>{}</title>"
          "</text><text class=\"tick\" x=\"{}\" y=\"{:.1f}\" text-anchor=\"end\">{}<title>{}"
          "</title></text>",
          at, margin - 6, i + 1, name, margin - 6, at + 4, i + 1, name);
    }
  }
  return svg + "</svg>";
}

std::string StageTimesSvg(const std::vector<std::pair<std::string, double>>& stages, int width) {
  double total = 0;
  for (const auto& [name, seconds] : stages) total += std::max(0.0, seconds);
  if (!(total > 0)) return "";
  const int bar = 22, legend = 20;
  std::string svg = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"chart\" width=\"{0}\" height=\"{1}\" "
      "viewBox=\"0 0 {0} {1}\">",
      width, bar + legend + 8);
  double x = 0;
  double legend_x = 0;
  for (size_t i = 0; i < stages.size(); ++i) {
    const auto& [name, seconds] = stages[i];
    const double w = std::max(0.0, seconds) / total * width;
    const std::string color = ViridisHex(stages.size() > 1 ? i / (stages.size() - 1.0) : 0.5);
    // The map stage's phases on a small set take milliseconds, which "0.0 s" would hide.
    const std::string text = seconds < 0.095 ? fmt::format("{} {:.0f} ms", name, 1000 * seconds)
                                             : fmt::format("{} {:.1f} s", name, seconds);
    svg += fmt::format(
        "<rect x=\"{:.1f}\" y=\"0\" width=\"{:.1f}\" height=\"{}\" fill=\"{}\"><title>{} "
        "({:.0f} %)</title></rect>",
        x, w, bar, color, EscapeHtml(text), 100 * seconds / total);
    svg += fmt::format(
        "<rect x=\"{:.1f}\" y=\"{}\" width=\"10\" height=\"10\" fill=\"{}\"/>"
        "<text class=\"tick\" x=\"{:.1f}\" y=\"{}\">{}</text>",
        legend_x, bar + 8, color, legend_x + 14, bar + 17, EscapeHtml(text));
    legend_x += 14 + 7.0 * text.size() + 14;
    x += w;
  }
  return svg + "</svg>";
}

std::string ColorBarSvg(double low, double high, const std::string& label, int decimals,
                        int width) {
  std::string svg = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"colorbar\" width=\"{0}\" height=\"38\" "
      "viewBox=\"0 0 {0} 38\"><defs><linearGradient id=\"viridis\">",
      width);
  for (int i = 0; i <= 8; ++i)
    svg += fmt::format("<stop offset=\"{:.3f}\" stop-color=\"{}\"/>", i / 8.0, ViridisHex(i / 8.0));
  svg += fmt::format(
      "</linearGradient></defs><text class=\"tick\" x=\"0\" y=\"10\">{}</text>"
      "<rect x=\"0\" y=\"14\" width=\"{}\" height=\"10\" fill=\"url(#viridis)\"/>"
      "<text class=\"tick\" x=\"0\" y=\"36\">{:.{}f}</text>"
      "<text class=\"tick\" x=\"{}\" y=\"36\" text-anchor=\"end\">{:.{}f}</text></svg>",
      EscapeHtml(label), width, low, decimals, width, high, decimals);
  return svg;
}

}  // namespace varsfm
