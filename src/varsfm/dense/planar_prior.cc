#include "varsfm/dense/planar_prior.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "varsfm/util/option_check.h"

namespace varsfm {
namespace {

struct Anchor {
  int x = 0, y = 0;
  Eigen::Vector3f point;  // camera frame
};

// The lowest-cost confident pixel of every anchor_cell x anchor_cell cell, row-major.
std::vector<Anchor> SelectAnchors(const DepthMap& map, const Eigen::Matrix3f& K_inv,
                                  const PlanarPriorOptions& options) {
  std::vector<Anchor> anchors;
  const int cell = options.anchor_cell;
  for (int cy = 0; cy < map.height; cy += cell)
    for (int cx = 0; cx < map.width; cx += cell) {
      float best_cost = static_cast<float>(options.anchor_max_cost);
      int best = -1;
      for (int y = cy; y < std::min(cy + cell, map.height); ++y)
        for (int x = cx; x < std::min(cx + cell, map.width); ++x) {
          const size_t i = map.Index(x, y);
          if (map.depth[i] > 0 && map.cost[i] <= best_cost)
            best_cost = map.cost[i], best = static_cast<int>(i);
        }
      if (best < 0) continue;
      const int x = best % map.width, y = best / map.width;
      const float d = map.depth[static_cast<size_t>(best)];
      anchors.push_back({x, y, d * (K_inv * Eigen::Vector3f(x + 0.5f, y + 0.5f, 1.0f))});
    }
  return anchors;
}

}  // namespace

DepthMap BuildPlanarPrior(const DepthMap& map, const Eigen::Matrix3d& K,
                          const PlanarPriorOptions& options) {
  DepthMap prior;
  prior.width = map.width;
  prior.height = map.height;
  const size_t n = static_cast<size_t>(map.width) * map.height;
  prior.depth.assign(n, 0);
  prior.normal.assign(n, Eigen::Vector3f::Zero());
  prior.cost.assign(n, 0);
  const Eigen::Matrix3f K_inv = K.inverse().cast<float>();
  const std::vector<Anchor> anchors = SelectAnchors(map, K_inv, options);
  if (anchors.size() < 3) return prior;

  // Delaunay triangulation of the anchors' pixel centres. Each anchor is the only one in its
  // pixel, so a triangle's corner names its anchor through the pixel it lies in.
  cv::Subdiv2D subdiv(cv::Rect(0, 0, map.width, map.height));
  std::vector<int> anchor_at(n, -1);
  for (size_t k = 0; k < anchors.size(); ++k) {
    subdiv.insert(cv::Point2f(anchors[k].x + 0.5f, anchors[k].y + 0.5f));
    anchor_at[map.Index(anchors[k].x, anchors[k].y)] = static_cast<int>(k);
  }
  std::vector<cv::Vec6f> triangles;
  subdiv.getTriangleList(triangles);

  const float max_edge =
      static_cast<float>(options.max_edge_fraction * std::max(map.width, map.height));
  const float min_cos =
      static_cast<float>(std::cos(options.max_view_angle_deg * std::numbers::pi / 180.0));
  for (const cv::Vec6f& t : triangles) {
    std::array<const Anchor*, 3> corner{};
    bool inside = true;
    for (int c = 0; c < 3 && inside; ++c) {
      const float u = t[2 * c], v = t[2 * c + 1];
      // Corners outside the image are Subdiv2D's virtual outer vertices.
      if (!(u >= 0 && v >= 0 && u < map.width && v < map.height)) {
        inside = false;
        break;
      }
      const int k = anchor_at[map.Index(static_cast<int>(u), static_cast<int>(v))];
      if (k < 0)
        inside = false;
      else
        corner[c] = &anchors[static_cast<size_t>(k)];
    }
    if (!inside) continue;
    const Eigen::Vector2f a(corner[0]->x + 0.5f, corner[0]->y + 0.5f);
    const Eigen::Vector2f b(corner[1]->x + 0.5f, corner[1]->y + 0.5f);
    const Eigen::Vector2f c(corner[2]->x + 0.5f, corner[2]->y + 0.5f);
    if ((b - a).norm() > max_edge || (c - b).norm() > max_edge || (a - c).norm() > max_edge)
      continue;
    Eigen::Vector3f normal =
        (corner[1]->point - corner[0]->point).cross(corner[2]->point - corner[0]->point);
    if (!(normal.norm() > 0)) continue;
    normal.normalize();
    const Eigen::Vector3f centroid_ray =
        (corner[0]->point + corner[1]->point + corner[2]->point).normalized();
    if (normal.dot(centroid_ray) > 0) normal = -normal;  // facing the camera
    if (-normal.dot(centroid_ray) < min_cos) continue;
    const float offset = normal.dot(corner[0]->point);  // n^T X = offset on the plane
    // Fill the pixels whose centres lie inside (edges included: a shared edge's pixel takes the
    // first triangle's plane).
    const float area = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    if (std::abs(area) < 1e-6f) continue;
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x(), b.x(), c.x()}))));
    const int x1 = std::min(map.width - 1, static_cast<int>(std::max({a.x(), b.x(), c.x()})));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y(), b.y(), c.y()}))));
    const int y1 = std::min(map.height - 1, static_cast<int>(std::max({a.y(), b.y(), c.y()})));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const Eigen::Vector2f p(x + 0.5f, y + 0.5f);
        const float w0 = ((b - p).x() * (c - p).y() - (b - p).y() * (c - p).x()) / area;
        const float w1 = ((c - p).x() * (a - p).y() - (c - p).y() * (a - p).x()) / area;
        const float w2 = 1 - w0 - w1;
        if (w0 < -1e-5f || w1 < -1e-5f || w2 < -1e-5f) continue;
        const size_t i = prior.Index(x, y);
        if (prior.depth[i] > 0) continue;
        const Eigen::Vector3f ray = K_inv * Eigen::Vector3f(p.x(), p.y(), 1.0f);
        const float along = normal.dot(ray);
        if (!(along < 0)) continue;
        const float depth = offset / along;
        if (!(depth > 0)) continue;
        prior.depth[i] = depth;
        prior.normal[i] = normal;
      }
  }
  return prior;
}

void PlanarPriorOptions::Check() const {
  CheckInRange("--dense-planar-iterations", num_iterations, 0, 50);
  CheckInRange("planar prior anchor_max_cost", anchor_max_cost, 0.0, 2.0);
  CheckInRange("planar prior anchor_cell", anchor_cell, 1, 64);
  CheckInRange("planar prior max_edge_fraction", max_edge_fraction, 0.0, 1.0);
  CheckInRange("planar prior max_view_angle_deg", max_view_angle_deg, 0.0, 90.0);
}

}  // namespace varsfm
