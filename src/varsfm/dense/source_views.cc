#include "varsfm/dense/source_views.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "varsfm/geometry/triangulation.h"
#include "varsfm/util/option_check.h"

namespace varsfm {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

// The size of a pixel at X in the image (depth / focal length).
double Footprint(const Reconstruction& rec, image_t id, const Eigen::Vector3d& X) {
  const double depth = (rec.image(id).cam_from_world * X).z();
  return depth / rec.CameraOf(id).params[Camera::kFocal];
}

// Goesele et al. 2007, eq. 3: r = footprint in the reference / footprint in the source.
double ScaleWeight(double r) {
  if (r >= 2) return 2 / r;
  if (r >= 1) return 1;
  return r;
}

}  // namespace

std::vector<image_t> RegisteredViews(const Reconstruction& rec, const Point3D& point) {
  std::vector<image_t> views;
  for (const TrackElement& el : point.track)
    if (rec.ExistsImage(el.image_id) && rec.image(el.image_id).registered)
      views.push_back(el.image_id);
  std::sort(views.begin(), views.end());
  views.erase(std::unique(views.begin(), views.end()), views.end());
  return views;
}

std::map<image_t, std::vector<image_t>> SelectSourceViews(const Reconstruction& rec,
                                                          const SourceViewOptions& options) {
  struct Score {
    double score = 0;
    int shared = 0;
  };
  std::map<std::pair<image_t, image_t>, Score> scores;  // (reference, source)
  const double min_angle = options.min_angle_deg * kDegToRad;
  const double good_angle = options.good_angle_deg * kDegToRad;
  for (const auto& [id, point] : rec.points3D()) {
    const std::vector<image_t> views = RegisteredViews(rec, point);
    for (image_t r : views)
      for (image_t s : views) {
        if (r == s) continue;
        Score& score = scores[{r, s}];
        ++score.shared;
        const double angle =
            TriangulationAngle(rec.image(r).Center(), rec.image(s).Center(), point.xyz);
        if (angle < min_angle) continue;
        const double w_angle = std::pow(std::min(angle / good_angle, 1.0), 2);
        const double ratio = Footprint(rec, r, point.xyz) / Footprint(rec, s, point.xyz);
        score.score += w_angle * ScaleWeight(ratio);
      }
  }
  std::map<image_t, std::vector<std::pair<double, image_t>>> candidates;
  for (const auto& [pair, score] : scores)
    if (score.shared >= options.min_shared_points && score.score > 0)
      candidates[pair.first].push_back({score.score, pair.second});
  std::map<image_t, std::vector<image_t>> sources;
  for (auto& [reference, list] : candidates) {
    std::sort(list.begin(), list.end(), [](const auto& a, const auto& b) {
      return a.first != b.first ? a.first > b.first : a.second < b.second;
    });
    const size_t n = std::min(list.size(), static_cast<size_t>(options.num_source_views));
    for (size_t i = 0; i < n; ++i) sources[reference].push_back(list[i].second);
  }
  return sources;
}

DepthRange SparseDepthRange(const Reconstruction& rec, image_t image_id, double percentile) {
  const Image& image = rec.image(image_id);
  std::vector<double> depths;
  for (const Point2D& p : image.points2D) {
    if (p.point3D_id == kInvalidPoint3DId || !rec.ExistsPoint3D(p.point3D_id)) continue;
    const double z = (image.cam_from_world * rec.point3D(p.point3D_id).xyz).z();
    if (z > 0) depths.push_back(z);
  }
  if (depths.empty()) return {};
  std::sort(depths.begin(), depths.end());
  const size_t last = depths.size() - 1;
  const auto skipped = static_cast<size_t>(static_cast<double>(last) * percentile / 100.0);
  // On a ground plane running towards the camera the nearest few points are the surface, not
  // outliers (percentile 0 keeps them). A point nearer than a tenth of the median depth is taken
  // for an outlier all the same: inverse-depth draws would otherwise go mostly in front of the
  // scene.
  const double median = depths[depths.size() / 2];
  const double nearest =
      std::max(depths[skipped], *std::lower_bound(depths.begin(), depths.end(), 0.1 * median));
  return {0.75 * nearest, 1.25 * depths[last - skipped]};
}

void SourceViewOptions::Check() const {
  CheckInRange("--dense-source-views", num_source_views, 1, 16);
  CheckAtLeast("source view min_shared_points", min_shared_points, 1);
  CheckInRange("source view min_angle_deg", min_angle_deg, 0.0, 90.0);
  CheckInRange("source view good_angle_deg", good_angle_deg, 0.1, 90.0);
  CheckInRange("--dense-depth-range-percentile", depth_range_percentile, 0.0, 25.0);
}

}  // namespace varsfm
