#include "varsfm/texture/texture_charts.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <opencv2/imgproc.hpp>

namespace varsfm {
namespace {

// Marks the texels of `mask` whose square overlaps triangle p (pixel coordinates of the mask):
// those whose centre lies within half a texel diagonal outside every edge line.
void MarkTriangle(const std::array<Eigen::Vector2d, 3>& p, cv::Mat* mask) {
  for (const Eigen::Vector2d& corner : p) {  // so a degenerate face still has its texels
    const int x = std::clamp(static_cast<int>(std::floor(corner.x())), 0, mask->cols - 1);
    const int y = std::clamp(static_cast<int>(std::floor(corner.y())), 0, mask->rows - 1);
    mask->at<uchar>(y, x) = 255;
  }
  const double area2 =
      (p[1] - p[0]).x() * (p[2] - p[0]).y() - (p[1] - p[0]).y() * (p[2] - p[0]).x();
  if (std::abs(area2) < 1e-9) return;
  constexpr double kHalfDiagonal = 0.7072;
  Eigen::Vector2d normal[3];  // unit, pointing inside
  double offset[3];
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector2d& u = p[(k + 1) % 3];
    const Eigen::Vector2d& v = p[(k + 2) % 3];
    const Eigen::Vector2d d = v - u;
    normal[k] = Eigen::Vector2d(-d.y(), d.x()) * (area2 > 0 ? 1.0 : -1.0) / d.norm();
    offset[k] = normal[k].dot(u);
  }
  const auto lo = [](double a, double b, double c) { return std::min({a, b, c}); };
  const auto hi = [](double a, double b, double c) { return std::max({a, b, c}); };
  const int x0 = std::max(0, static_cast<int>(std::floor(lo(p[0].x(), p[1].x(), p[2].x()) - 1)));
  const int y0 = std::max(0, static_cast<int>(std::floor(lo(p[0].y(), p[1].y(), p[2].y()) - 1)));
  const int x1 = std::min(mask->cols - 1, static_cast<int>(hi(p[0].x(), p[1].x(), p[2].x()) + 1));
  const int y1 = std::min(mask->rows - 1, static_cast<int>(hi(p[0].y(), p[1].y(), p[2].y()) + 1));
  for (int y = y0; y <= y1; ++y) {
    uchar* row = mask->ptr<uchar>(y);
    for (int x = x0; x <= x1; ++x) {
      const Eigen::Vector2d q(x + 0.5, y + 0.5);
      bool overlaps = true;
      for (int k = 0; k < 3 && overlaps; ++k)
        overlaps = normal[k].dot(q) - offset[k] >= -kHalfDiagonal;
      if (overlaps) row[x] = 255;
    }
  }
}

}  // namespace

std::vector<Chart> GrowCharts(const std::vector<int>& labels,
                              const std::vector<std::array<int, 3>>& neighbours) {
  std::vector<Chart> charts;
  std::vector<char> done(labels.size(), 0);
  std::vector<int> stack;
  for (size_t seed = 0; seed < labels.size(); ++seed) {
    if (done[seed] || labels[seed] < 0) continue;
    Chart chart;
    chart.view = labels[seed];
    stack.assign(1, static_cast<int>(seed));
    done[seed] = 1;
    while (!stack.empty()) {
      const int f = stack.back();
      stack.pop_back();
      chart.faces.push_back(f);
      for (const int g : neighbours[f]) {
        if (g >= 0 && !done[g] && labels[g] == chart.view) {
          done[g] = 1;
          stack.push_back(g);
        }
      }
    }
    charts.push_back(std::move(chart));
  }
  return charts;
}

std::vector<Chart> CutChart(const Chart& chart, const std::vector<Eigen::Vector3i>& faces,
                            const std::vector<ProjectedVertex>& pixels, int tile) {
  std::vector<Chart> pieces;
  std::map<std::pair<int, int>, size_t> piece_of_square;
  for (const int f : chart.faces) {
    const Eigen::Vector2d centroid =
        (pixels[faces[f][0]].pixel + pixels[faces[f][1]].pixel + pixels[faces[f][2]].pixel) / 3;
    const std::pair<int, int> square(static_cast<int>(std::floor(centroid.x() / tile)),
                                     static_cast<int>(std::floor(centroid.y() / tile)));
    const auto [it, inserted] = piece_of_square.try_emplace(square, pieces.size());
    if (inserted) {
      pieces.emplace_back();
      pieces.back().view = chart.view;
    }
    pieces[it->second].faces.push_back(f);
  }
  return pieces;
}

double SetChartMask(const std::vector<Eigen::Vector3i>& faces,
                    const std::vector<ProjectedVertex>& pixels, cv::Size photo_size, int gutter,
                    Chart* chart) {
  double face_texels = 0;
  const int margin = gutter + 1;
  double min_x = 1e300, min_y = 1e300, max_x = -1e300, max_y = -1e300;
  for (const int f : chart->faces) {
    const Eigen::Vector2d& a = pixels[faces[f][0]].pixel;
    const Eigen::Vector2d e1 = pixels[faces[f][1]].pixel - a;
    const Eigen::Vector2d e2 = pixels[faces[f][2]].pixel - a;
    face_texels += 0.5 * std::abs(e1.x() * e2.y() - e1.y() * e2.x());
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2d& p = pixels[faces[f][k]].pixel;
      min_x = std::min(min_x, p.x());
      min_y = std::min(min_y, p.y());
      max_x = std::max(max_x, p.x());
      max_y = std::max(max_y, p.y());
    }
  }
  const int mx = photo_size.width / 4, my = photo_size.height / 4;
  const int x0 = std::max(-mx, static_cast<int>(std::floor(min_x)) - margin);
  const int y0 = std::max(-my, static_cast<int>(std::floor(min_y)) - margin);
  const int x1 = std::min(photo_size.width + mx, static_cast<int>(std::ceil(max_x)) + margin);
  const int y1 = std::min(photo_size.height + my, static_cast<int>(std::ceil(max_y)) + margin);
  const cv::Rect box(x0, y0, std::max(1, x1 - x0), std::max(1, y1 - y0));
  cv::Mat mask(box.size(), CV_8UC1, cv::Scalar::all(0));
  const Eigen::Vector2d corner(box.x, box.y);
  for (const int f : chart->faces) {
    MarkTriangle({pixels[faces[f][0]].pixel - corner, pixels[faces[f][1]].pixel - corner,
                  pixels[faces[f][2]].pixel - corner},
                 &mask);
  }
  if (gutter > 0) {
    const cv::Mat square = cv::Mat::ones(2 * gutter + 1, 2 * gutter + 1, CV_8UC1);
    cv::dilate(mask, mask, square);
  }
  const cv::Rect used = cv::boundingRect(mask);  // trim the unused margin
  chart->source = cv::Rect(box.x + used.x, box.y + used.y, used.width, used.height);
  chart->mask = mask(used).clone();
  return face_texels;
}

}  // namespace varsfm
