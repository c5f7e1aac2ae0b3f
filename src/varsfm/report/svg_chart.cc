#include "varsfm/report/svg_chart.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "varsfm/report/html_text.h"

namespace varsfm {
namespace {

// Margins around the plotting area: room for the axis labels.
constexpr int kLeft = 64;
constexpr int kRight = 56;
constexpr int kTop = 28;
constexpr int kBottom = 58;

// Decimals that show a tick step exactly (step 0.05: 2).
int TickDecimals(double step) {
  return std::clamp(static_cast<int>(std::ceil(-std::log10(step) - 1e-9)), 0, 8);
}

std::string Number(double value, int decimals) {
  if (std::abs(value) < 0.5 * std::pow(10.0, -decimals)) value = 0;  // no "-0.00"
  return fmt::format("{:.{}f}", value, decimals);
}

// Maps data values to SVG coordinates along one axis.
struct Scale {
  double data_low, data_high, pixel_low, pixel_high;
  double operator()(double v) const {
    return pixel_low + (v - data_low) / (data_high - data_low) * (pixel_high - pixel_low);
  }
};

std::string Open(const ChartFrame& frame) {
  std::string svg = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"chart\" width=\"{0}\" height=\"{1}\" "
      "viewBox=\"0 0 {0} {1}\">",
      frame.width, frame.height);
  if (!frame.title.empty())
    svg += fmt::format("<text class=\"title\" x=\"{}\" y=\"16\">{}</text>", kLeft,
                       EscapeHtml(frame.title));
  return svg;
}

// The y axis with grid lines at `ticks`, and the axis labels.
std::string YAxis(const ChartFrame& frame, const Scale& y, const std::vector<double>& ticks) {
  std::string svg;
  const int decimals = ticks.size() > 1 ? TickDecimals(ticks[1] - ticks[0]) : 0;
  for (const double t : ticks) {
    svg += fmt::format(
        "<line class=\"grid\" x1=\"{}\" x2=\"{}\" y1=\"{:.1f}\" y2=\"{:.1f}\"/>"
        "<text class=\"tick\" x=\"{}\" y=\"{:.1f}\" text-anchor=\"end\">{}</text>",
        kLeft, frame.width - kRight, y(t), y(t), kLeft - 6, y(t) + 4, Number(t, decimals));
  }
  svg += fmt::format(
      "<text class=\"label\" transform=\"translate(14 {}) rotate(-90)\" "
      "text-anchor=\"middle\">{}</text>",
      (kTop + frame.height - kBottom) / 2, EscapeHtml(frame.y_label));
  if (!frame.x_label.empty())
    svg += fmt::format("<text class=\"label\" x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>",
                       (kLeft + frame.width - kRight) / 2, frame.height - 6,
                       EscapeHtml(frame.x_label));
  return svg;
}

// Whether every image's name fits under its slot (else every k-th index is written).
bool NamesFit(double slot) { return slot >= 14; }

// Labels under the categories: every image's name when they fit, else every k-th index.
std::string CategoryLabels(const ChartFrame& frame, const std::vector<std::string>& names,
                           const Scale& x) {
  std::string svg;
  const size_t n = names.size();
  const double slot = (frame.width - kLeft - kRight) / std::max<double>(1, n);
  const int y = frame.height - kBottom + 12;
  if (NamesFit(slot)) {
    for (size_t i = 0; i < n; ++i) {
      std::string label = names[i];
      if (label.size() > 10) label = "\u2026" + label.substr(label.size() - 9);
      svg += fmt::format(
          "<text class=\"tick\" transform=\"translate({:.1f} {}) rotate(-40)\" "
          "text-anchor=\"end\">{}</text>",
          x(i) + 3, y, EscapeHtml(label));
    }
    return svg;
  }
  const size_t every = static_cast<size_t>(std::ceil(n / 10.0));
  for (size_t i = 0; i < n; i += every)
    svg +=
        fmt::format("<text class=\"tick\" x=\"{:.1f}\" y=\"{}\" text-anchor=\"middle\">{}</text>",
                    x(i), y + 2, i + 1);
  return svg;
}

// The value range to show: the data's, widened to a nice interval, never empty.
std::pair<double, double> ValueRange(const PerImageSeries& series) {
  double low = INFINITY, high = -INFINITY;
  for (const auto& v : series.values) {
    if (!v) continue;
    low = std::min(low, *v);
    high = std::max(high, *v);
  }
  if (series.reference) {
    low = std::min(low, *series.reference);
    high = std::max(high, *series.reference);
  }
  if (series.bars) low = std::min(low, 0.0);
  if (!std::isfinite(low)) return {0, 1};
  if (series.min_range) {
    low = std::min(low, series.min_range->first);
    high = std::max(high, series.min_range->second);
  }
  if (high - low < 1e-12 * std::max(1.0, std::abs(high))) {
    const double pad = std::max(std::abs(high) * 0.05, 1e-6);
    low -= pad;
    high += pad;
  }
  return {low, high};
}

}  // namespace

std::vector<double> NiceTicks(double low, double high, int target) {
  if (!(high > low)) high = low + 1;
  const double raw = (high - low) / std::max(1, target);
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  const double normalised = raw / magnitude;
  const double step = (normalised < 1.5 ? 1
                       : normalised < 3 ? 2
                       : normalised < 7 ? 5
                                        : 10) *
                      magnitude;
  std::vector<double> ticks;
  const double first = std::floor(low / step + 1e-9) * step;
  for (double t = first; t < high + step - 1e-9 * step && ticks.size() < 100; t += step)
    ticks.push_back(t);
  return ticks;
}

std::string PerImageChartSvg(const ChartFrame& frame, const PerImageSeries& series) {
  const auto [low, high] = ValueRange(series);
  const std::vector<double> ticks = NiceTicks(low, high);
  const size_t n = series.values.size();
  const double slot = (frame.width - kLeft - kRight) / std::max<double>(1, n);
  const Scale x{-0.5, n - 0.5, static_cast<double>(kLeft), static_cast<double>(kLeft + slot * n)};
  const Scale y{ticks.front(), ticks.back(), static_cast<double>(frame.height - kBottom),
                static_cast<double>(kTop)};
  // Slanted names reach down to the x axis' title; they say what the axis holds without it.
  ChartFrame axes = frame;
  if (NamesFit(slot)) axes.x_label.clear();
  std::string svg = Open(frame) + YAxis(axes, y, ticks) + CategoryLabels(frame, series.names, x);
  if (series.right_axis_unit && *series.right_axis_unit > 0) {
    const double unit = *series.right_axis_unit;
    const std::vector<double> ratios = NiceTicks(ticks.front() / unit, ticks.back() / unit);
    const int decimals = std::max(1, ratios.size() > 1 ? TickDecimals(ratios[1] - ratios[0]) : 1);
    for (const double r : ratios) {
      if (r * unit < ticks.front() - 1e-9 || r * unit > ticks.back() + 1e-9) continue;
      svg += fmt::format("<text class=\"tick\" x=\"{}\" y=\"{:.1f}\">\u00d7{}</text>",
                         frame.width - kRight + 6, y(r * unit) + 4, Number(r, decimals));
    }
  }
  if (series.reference) {
    svg += fmt::format(
        "<line class=\"reference\" x1=\"{}\" x2=\"{}\" y1=\"{:.1f}\" y2=\"{:.1f}\"><title>{}"
        "</title></line>",
        kLeft, frame.width - kRight, y(*series.reference), y(*series.reference),
        EscapeHtml(series.reference_label));
  }
  const auto color = [&](size_t i) {
    return i < series.colors.size() && !series.colors[i].empty() ? series.colors[i] : series.color;
  };
  const auto tooltip = [&](size_t i) {
    const std::string name = i < series.names.size() ? series.names[i] : "";
    return series.values[i] ? fmt::format("{}: {:.{}f}", name, *series.values[i], series.decimals)
                            : fmt::format("{}: not registered", name);
  };
  const auto id = [&](size_t i) { return i < series.image_ids.size() ? series.image_ids[i] : 0; };
  std::string path;
  for (size_t i = 0; i < n; ++i) {
    if (!series.values[i]) {
      svg += fmt::format(
          "<text class=\"missing\" x=\"{:.1f}\" y=\"{}\" text-anchor=\"middle\" "
          "data-image=\"{}\">\u00d7<title>{}</title></text>",
          x(i), frame.height - kBottom - 3, id(i), EscapeHtml(tooltip(i)));
      continue;
    }
    const double v = *series.values[i];
    if (series.bars) {
      const double top = std::min(y(v), y(0)), bottom = std::max(y(v), y(0));
      svg += fmt::format(
          "<rect class=\"mark\" x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\" "
          "fill=\"{}\" data-image=\"{}\"><title>{}</title></rect>",
          x(i) - slot * 0.35, top, slot * 0.7, std::max(0.5, bottom - top), color(i), id(i),
          EscapeHtml(tooltip(i)));
    } else {
      path += fmt::format("{}{:.1f},{:.1f}", path.empty() || !series.values[i - 1] ? " M" : " L",
                          x(i), y(v));
    }
  }
  if (!path.empty()) {
    svg += fmt::format("<path class=\"line\" d=\"{}\" stroke=\"{}\"/>", path, series.color);
    const double radius = std::clamp(slot * 0.3, 2.0, 6.0);
    for (size_t i = 0; i < n; ++i) {
      if (!series.values[i]) continue;
      svg += fmt::format(
          "<circle class=\"mark\" cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"{:.1f}\" fill=\"{}\" "
          "data-image=\"{}\"><title>{}</title></circle>",
          x(i), y(*series.values[i]), radius, color(i), id(i), EscapeHtml(tooltip(i)));
    }
  }
  return svg + "</svg>";
}

std::string HistogramSvg(const ChartFrame& frame, const Histogram& histogram) {
  const int num_bins = histogram.integers ? std::max(1, static_cast<int>(histogram.upper))
                                          : std::max(1, histogram.num_bins);
  const double upper = histogram.integers ? num_bins : histogram.upper > 0 ? histogram.upper : 1;
  std::vector<size_t> counts(num_bins, 0);
  bool clipped = false;
  for (const double v : histogram.values) {
    const int bin = static_cast<int>(std::floor(v / upper * num_bins));
    clipped |= bin >= num_bins;
    ++counts[std::clamp(bin, 0, num_bins - 1)];
  }
  const size_t most = *std::max_element(counts.begin(), counts.end());
  const std::vector<double> ticks = NiceTicks(0, std::max<double>(1, most));
  const Scale x{0, upper, static_cast<double>(kLeft), static_cast<double>(frame.width - kRight)};
  const Scale y{0, ticks.back(), static_cast<double>(frame.height - kBottom),
                static_cast<double>(kTop)};
  std::string svg = Open(frame) + YAxis(frame, y, ticks);
  const double width = upper / num_bins;
  for (int b = 0; b < num_bins; ++b) {
    if (histogram.integers && counts[b] == 0) continue;
    const double from = b * width, to = from + width;
    const bool last_clipped = clipped && b == num_bins - 1;
    std::string range;
    if (histogram.integers)
      range = fmt::format("{}{}", b, last_clipped ? "+" : "");
    else
      range = last_clipped ? fmt::format("\u2265 {:.3g}", from)
                           : fmt::format("{:.3g} \u2013 {:.3g}", from, to);
    svg += fmt::format(
        "<rect class=\"mark\" x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\" "
        "fill=\"{}\"><title>{}: {}</title></rect>",
        x(from) + 0.5, y(counts[b]), std::max(0.5, x(to) - x(from) - 1), y(0) - y(counts[b]),
        histogram.color, range, counts[b]);
  }
  const std::vector<double> x_ticks = NiceTicks(0, upper, 6);
  const int decimals = x_ticks.size() > 1 ? TickDecimals(x_ticks[1] - x_ticks[0]) : 0;
  for (const double t : x_ticks) {
    if (t > upper + 1e-9 || (histogram.integers && t > upper - 1)) break;
    const bool plus = clipped && std::abs(t - (histogram.integers ? upper - 1 : upper)) < 1e-9;
    const double at = histogram.integers ? x(t + 0.5) : x(t);
    svg +=
        fmt::format("<text class=\"tick\" x=\"{:.1f}\" y=\"{}\" text-anchor=\"middle\">{}{}</text>",
                    at, frame.height - kBottom + 14, Number(t, decimals), plus ? "+" : "");
  }
  return svg + "</svg>";
}

}  // namespace varsfm
