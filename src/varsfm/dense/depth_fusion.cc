#include "varsfm/dense/depth_fusion.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include <tbb/parallel_for.h>

#include "varsfm/util/option_check.h"
#include "varsfm/util/progress.h"

namespace varsfm {
namespace {

// A view's projection, precomputed once.
struct ViewGeometry {
  Eigen::Matrix3d K, K_inv, R;
  Eigen::Vector3d t;
  int width = 0, height = 0;

  explicit ViewGeometry(const FusionView& v)
      : K(v.K),
        K_inv(v.K.inverse()),
        R(v.cam_from_world.R()),
        t(v.cam_from_world.translation),
        width(v.map.width),
        height(v.map.height) {}

  // The world point at pixel (x, y) (its centre) and depth.
  Eigen::Vector3d Unproject(int x, int y, double depth) const {
    return UnprojectAt(Eigen::Vector2d(x + 0.5, y + 0.5), depth);
  }
  Eigen::Vector3d UnprojectAt(const Eigen::Vector2d& pixel, double depth) const {
    const Eigen::Vector3d camera = depth * (K_inv * pixel.homogeneous());
    return R.transpose() * (camera - t);
  }

  // The pixel X falls in and its depth; false behind the camera or outside the image.
  bool Project(const Eigen::Vector3d& X, Eigen::Vector2d* pixel, double* depth) const {
    const Eigen::Vector3d h = K * (R * X + t);
    if (h.z() <= 0) return false;
    *pixel = h.hnormalized();
    *depth = h.z();
    return pixel->x() >= 0 && pixel->y() >= 0 && pixel->x() < width && pixel->y() < height;
  }
};

size_t PixelIndex(const ViewGeometry& g, const Eigen::Vector2d& pixel) {
  return static_cast<size_t>(pixel.y()) * g.width + static_cast<size_t>(pixel.x());
}

// The depth at sub-pixel `q` of the plane hypothesis of the pixel q falls in (index j: its depth
// at the pixel's centre and its normal), where the ray through q meets that plane. A depth map
// holds a plane per pixel, not a constant: read at the pixel's centre, a surface seen at a
// grazing angle changes depth within the half pixel between q and that centre by as much as the
// tolerances allow, so the tests measured the pixel grid rather than the views' disagreement.
// With the extra source views of surfaces seen from one side (source_views.h) it is what keeps
// their depths from costing held-out PSNR (bench/results/2026-12-05-s17-coverage-source.md).
// The pixel's own depth where the plane is too oblique to the ray to extrapolate.
double PlaneDepthAt(const DepthMap& map, size_t j, const ViewGeometry& g,
                    const Eigen::Vector2d& q) {
  const double depth = map.depth[j];
  if (map.normal.empty()) return depth;
  const Eigen::Vector3d n = map.normal[j].cast<double>();
  const Eigen::Vector2d centre(std::floor(q.x()) + 0.5, std::floor(q.y()) + 0.5);
  const Eigen::Vector3d ray_q = g.K_inv * q.homogeneous();  // z = 1: depth along the axis
  const Eigen::Vector3d on_plane = depth * (g.K_inv * centre.homogeneous());
  const double along = n.dot(ray_q);
  if (std::abs(along) < 0.1 * ray_q.norm()) return depth;  // within ~6 deg of the plane
  return n.dot(on_plane) / along;
}

// Where X meets view u: the pixel it falls in, the sub-pixel position, X's own depth there, and
// the depth of u's surface at that position (PlaneDepthAt).
struct ViewHit {
  size_t pixel;
  Eigen::Vector2d position;
  double point_depth;
  double surface_depth;
};

// Nothing when X falls behind or outside u, or where u has no (positive) surface depth.
std::optional<ViewHit> HitInView(const FusionView& view, const ViewGeometry& g,
                                 const Eigen::Vector3d& X) {
  ViewHit hit;
  if (!g.Project(X, &hit.position, &hit.point_depth)) return std::nullopt;
  hit.pixel = PixelIndex(g, hit.position);
  if (view.map.depth[hit.pixel] <= 0) return std::nullopt;
  hit.surface_depth = PlaneDepthAt(view.map, hit.pixel, g, hit.position);
  if (hit.surface_depth <= 0) return std::nullopt;
  return hit;
}

// f(u) for every view u that view v's depths are checked against and fused with, in index order.
template <typename F>
void ForEachOverlappingView(const std::vector<FusionView>& views, size_t v, F&& f) {
  if (views[v].overlapping.empty()) {
    for (size_t u = 0; u < views.size(); ++u)
      if (u != v) f(u);
    return;
  }
  for (const uint32_t u : views[v].overlapping) f(u);
}

// How many other views confirm the depth of pixel (x, y) of view v: their depth where the point
// projects, unprojected and projected back into v, lands within the reprojection tolerance of
// the pixel at the same depth.
int ConsistentViews(const std::vector<FusionView>& views, const std::vector<ViewGeometry>& geometry,
                    size_t v, int x, int y, const DepthFusionOptions& options) {
  const ViewGeometry& g = geometry[v];
  const double depth = views[v].map.depth[views[v].map.Index(x, y)];
  const Eigen::Vector3d X = g.Unproject(x, y, depth);
  const Eigen::Vector2d centre(x + 0.5, y + 0.5);
  const double max_error2 = options.max_reprojection_error * options.max_reprojection_error;
  int consistent = 0;
  ForEachOverlappingView(views, v, [&](size_t u) {
    const std::optional<ViewHit> hit = HitInView(views[u], geometry[u], X);
    if (!hit) return;
    const Eigen::Vector3d back = geometry[u].UnprojectAt(hit->position, hit->surface_depth);
    Eigen::Vector2d p;
    double depth_back;
    if (!g.Project(back, &p, &depth_back)) return;
    if ((p - centre).squaredNorm() <= max_error2 &&
        std::abs(depth_back - depth) <= options.max_depth_difference * depth)
      ++consistent;
  });
  return consistent;
}

// Whether depth i of `map` is confident enough to stand on two views (two_view_max_cost).
bool TwoViewDepth(const DepthMap& map, size_t i, const DepthFusionOptions& options) {
  return options.two_view_max_cost > 0 && !map.cost.empty() &&
         map.cost[i] <= options.two_view_max_cost;
}

}  // namespace

void FilterByGeometricConsistency(std::vector<FusionView>* views,
                                  const DepthFusionOptions& options) {
  std::vector<ViewGeometry> geometry;
  for (const FusionView& v : *views) geometry.emplace_back(v);
  std::vector<std::vector<uint8_t>> keep(views->size());
  Progress progress("depth consistency", views->size());
  tbb::parallel_for(size_t{0}, views->size(), [&](size_t v) {
    const DepthMap& map = (*views)[v].map;
    keep[v].assign(map.depth.size(), 0);
    tbb::parallel_for(0, map.height, [&](int y) {
      for (int x = 0; x < map.width; ++x)
        if (map.depth[map.Index(x, y)] > 0)
          keep[v][map.Index(x, y)] =
              ConsistentViews(*views, geometry, v, x, y, options) >=
              (TwoViewDepth(map, map.Index(x, y), options) ? options.FewestConfirmingViews()
                                                           : options.min_consistent_views);
    });
    progress.Tick();
  });
  for (size_t v = 0; v < views->size(); ++v) {
    DepthMap& map = (*views)[v].map;
    for (size_t i = 0; i < map.depth.size(); ++i)
      if (!keep[v][i]) map.depth[i] = 0;
  }
}

void FuseDepthMaps(const std::vector<FusionView>& views, const DepthFusionOptions& options,
                   const FusedPointSink& sink) {
  std::vector<ViewGeometry> geometry;
  for (const FusionView& v : views) geometry.emplace_back(v);
  std::vector<std::vector<uint8_t>> fused(views.size());
  for (size_t v = 0; v < views.size(); ++v) fused[v].assign(views[v].map.depth.size(), 0);
  const double min_cos = std::cos(options.max_normal_angle_deg * std::numbers::pi / 180.0);
  const auto world_normal = [&](size_t v, size_t i) {
    return geometry[v].R.transpose() * views[v].map.normal[i].cast<double>();
  };
  const auto color_at = [&](size_t v, size_t i) {
    const cv::Vec3b c = views[v].color.at<cv::Vec3b>(static_cast<int>(i));
    return Eigen::Vector3d(c[2], c[1], c[0]);  // BGR -> RGB
  };
  Progress progress("fusion", views.size());
  for (size_t v = 0; v < views.size(); ++v) {
    const DepthMap& map = views[v].map;
    for (int y = 0; y < map.height; ++y)
      for (int x = 0; x < map.width; ++x) {
        const size_t i = map.Index(x, y);
        if (map.depth[i] <= 0 || fused[v][i]) continue;
        const Eigen::Vector3d X = geometry[v].Unproject(x, y, map.depth[i]);
        const Eigen::Vector3d normal = world_normal(v, i);
        Eigen::Vector3d sum_x = X, sum_n = normal, sum_c = color_at(v, i);
        std::vector<image_t> seen_by = {views[v].image_id};
        std::vector<std::pair<size_t, size_t>> members = {{v, i}};
        ForEachOverlappingView(views, v, [&](size_t u) {
          const std::optional<ViewHit> hit = HitInView(views[u], geometry[u], X);
          if (!hit || fused[u][hit->pixel]) return;
          const size_t j = hit->pixel;
          const double depth_u = hit->point_depth, d = hit->surface_depth;
          if (std::abs(d - depth_u) > options.max_depth_difference * depth_u) return;
          const Eigen::Vector3d n = world_normal(u, j);
          if (n.dot(normal) < min_cos) return;
          members.push_back({u, j});
          sum_x += geometry[u].UnprojectAt(hit->position, d);
          sum_n += n;
          sum_c += color_at(u, j);
          seen_by.push_back(views[u].image_id);
        });
        // A pixel of a point too few views agree on stays free to join a later point.
        const int min_views = TwoViewDepth(map, i, options) ? std::min(options.min_fused_views, 2)
                                                            : options.min_fused_views;
        if (seen_by.size() < static_cast<size_t>(min_views)) continue;
        for (const auto& [view, pixel] : members) fused[view][pixel] = 1;
        const double count = static_cast<double>(seen_by.size());
        const Eigen::Vector3d c = sum_c / count;
        std::sort(seen_by.begin(), seen_by.end());
        sink({sum_x / count,
              sum_n.normalized(),
              {static_cast<uint8_t>(std::lround(c.x())), static_cast<uint8_t>(std::lround(c.y())),
               static_cast<uint8_t>(std::lround(c.z()))},
              std::move(seen_by)});
      }
    progress.Tick();
  }
}

FusedPointSink AppendTo(PointCloud* cloud, DenseVisibility* visibility) {
  return [cloud, visibility](FusedPoint&& p) {
    cloud->points.push_back(p.position);
    cloud->normals.push_back(p.normal);
    cloud->colors.push_back(p.color);
    if (visibility) visibility->push_back(std::move(p.seen_by));
  };
}

PointCloud FuseDepthMaps(const std::vector<FusionView>& views, const DepthFusionOptions& options,
                         DenseVisibility* visibility) {
  PointCloud cloud;
  if (visibility) visibility->clear();
  FuseDepthMaps(views, options, AppendTo(&cloud, visibility));
  return cloud;
}

void DepthFusionOptions::Check() const {
  CheckPositive("fusion max_reprojection_error", max_reprojection_error);
  CheckPositive("fusion max_depth_difference", max_depth_difference);
  CheckInRange("fusion max_normal_angle_deg", max_normal_angle_deg, 0.0, 180.0);
  CheckInRange("--dense-min-consistent", min_consistent_views, 0, 64);
  CheckAtLeast("fusion max_overlapping_views", max_overlapping_views, 1);
  // A point joins its view and at most max_overlapping_views others.
  CheckInRange("--dense-min-views", min_fused_views, 1, max_overlapping_views + 1);
  CheckInRange("--dense-two-view-cost", two_view_max_cost, 0.0, 2.0);
}

}  // namespace varsfm
