#include "varsfm/texture/chart_colour.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace varsfm {

void CorrectChartColours(const std::vector<std::array<Eigen::Vector2d, 3>>& face_pixels,
                         const std::vector<std::array<Eigen::Vector3f, 3>>& face_corrections,
                         const Eigen::Vector3f& gain, double reach, cv::Mat* chart) {
  const int w = chart->cols, h = chart->rows;
  cv::Mat correction(h, w, CV_32FC3, cv::Scalar::all(0));
  cv::Mat distance(h, w, CV_32FC1, cv::Scalar::all(std::numeric_limits<float>::infinity()));
  for (size_t f = 0; f < face_pixels.size(); ++f) {
    const std::array<Eigen::Vector2d, 3>& p = face_pixels[f];
    const double area2 =
        (p[1] - p[0]).x() * (p[2] - p[0]).y() - (p[1] - p[0]).y() * (p[2] - p[0]).x();
    if (std::abs(area2) < 1e-9) continue;  // degenerate: its neighbours cover its texels
    // Height of the triangle over the edge opposite each corner: a barycentric coordinate of
    // -b at that corner is a distance b x height outside that edge.
    double height[3];
    for (int k = 0; k < 3; ++k)
      height[k] = std::abs(area2) / std::max(1e-12, (p[(k + 2) % 3] - p[(k + 1) % 3]).norm());
    const int x0 =
        std::max(0, static_cast<int>(std::floor(std::min({p[0].x(), p[1].x(), p[2].x()}) - reach)));
    const int y0 =
        std::max(0, static_cast<int>(std::floor(std::min({p[0].y(), p[1].y(), p[2].y()}) - reach)));
    const int x1 = std::min(
        w - 1, static_cast<int>(std::ceil(std::max({p[0].x(), p[1].x(), p[2].x()}) + reach)));
    const int y1 = std::min(
        h - 1, static_cast<int>(std::ceil(std::max({p[0].y(), p[1].y(), p[2].y()}) + reach)));
    for (int y = y0; y <= y1; ++y) {
      float* d = distance.ptr<float>(y);
      cv::Vec3f* c = correction.ptr<cv::Vec3f>(y);
      for (int x = x0; x <= x1; ++x) {
        const Eigen::Vector2d q(x + 0.5, y + 0.5);
        double b[3];
        for (int k = 0; k < 3; ++k) {
          const Eigen::Vector2d& u = p[(k + 1) % 3];
          const Eigen::Vector2d& v = p[(k + 2) % 3];
          b[k] = ((v - u).x() * (q - u).y() - (v - u).y() * (q - u).x()) / area2;
        }
        double outside = 0;
        for (int k = 0; k < 3; ++k) outside = std::max(outside, -b[k] * height[k]);
        if (outside > reach || outside >= d[x]) continue;
        double sum = 0;
        for (double& bk : b) sum += (bk = std::max(0.0, bk));
        Eigen::Vector3f value = Eigen::Vector3f::Zero();
        for (int k = 0; k < 3; ++k)
          value += static_cast<float>(b[k] / sum) * face_corrections[f][k];
        c[x] = cv::Vec3f(value[0], value[1], value[2]);
        d[x] = static_cast<float>(outside);
      }
    }
  }
  for (int y = 0; y < h; ++y) {
    cv::Vec3b* t = chart->ptr<cv::Vec3b>(y);
    const cv::Vec3f* c = correction.ptr<cv::Vec3f>(y);
    for (int x = 0; x < w; ++x)
      for (int k = 0; k < 3; ++k) t[x][k] = cv::saturate_cast<uchar>(t[x][k] * gain[k] + c[x][k]);
  }
}

}  // namespace varsfm
