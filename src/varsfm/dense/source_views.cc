#include "varsfm/dense/source_views.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <unordered_map>

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
  const double min_angle = options.min_angle_deg * kDegToRad;
  const double good_angle = options.good_angle_deg * kDegToRad;
  // What one point adds to one candidate's score (Goesele et al. 2007, eq. 2).
  struct Contribution {
    image_t source;
    int point;  // index among the reference's points
    double weight;
  };
  std::map<image_t, std::vector<image_t>> sources;
  for (const image_t reference : rec.RegisteredImageIds()) {
    // The reference's points in id order, each once.
    std::vector<point3D_t> point_ids;
    for (const Point2D& p : rec.image(reference).points2D)
      if (p.point3D_id != kInvalidPoint3DId && rec.ExistsPoint3D(p.point3D_id))
        point_ids.push_back(p.point3D_id);
    std::sort(point_ids.begin(), point_ids.end());
    point_ids.erase(std::unique(point_ids.begin(), point_ids.end()), point_ids.end());
    std::vector<Contribution> list;
    std::map<image_t, int> shared;
    for (int k = 0; k < static_cast<int>(point_ids.size()); ++k) {
      const Point3D& point = rec.point3D(point_ids[k]);
      for (const image_t s : RegisteredViews(rec, point)) {
        if (s == reference) continue;
        ++shared[s];
        const double angle =
            TriangulationAngle(rec.image(reference).Center(), rec.image(s).Center(), point.xyz);
        if (angle < min_angle) continue;
        const double w_angle = std::pow(std::min(angle / good_angle, 1.0), 2);
        const double ratio = Footprint(rec, reference, point.xyz) / Footprint(rec, s, point.xyz);
        list.push_back({s, k, w_angle * ScaleWeight(ratio)});
      }
    }
    // Greedy, one source at a time: a point already seen by covered_views chosen sources counts
    // redundant_point_weight times its weight, so that the later sources cover the parts of the
    // reference the first ones do not see (its image's edges, surfaces seen from one side)
    // rather than see its centre again. With weight 1 this is the ranking by Goesele's score.
    std::erase_if(list, [&](const Contribution& c) {  // not a candidate: too few shared points
      return shared[c.source] < options.min_shared_points;
    });
    std::vector<int> covered(point_ids.size(), 0);
    std::vector<image_t> chosen;
    while (static_cast<int>(chosen.size()) < options.num_source_views) {
      std::map<image_t, double> score;
      for (const Contribution& c : list)
        score[c.source] +=
            c.weight *
            (covered[c.point] < options.covered_views ? 1.0 : options.redundant_point_weight);
      image_t best = kInvalidImageId;
      double best_score = 0;
      for (const auto& [source, value] : score)  // ascending ids: ties go to the lower id
        if (value > best_score && std::find(chosen.begin(), chosen.end(), source) == chosen.end())
          best = source, best_score = value;
      if (best == kInvalidImageId) break;
      chosen.push_back(best);
      for (const Contribution& c : list)
        if (c.source == best) ++covered[c.point];
    }
    // One more source for what none of the chosen ones sees, when a view sees enough of it:
    // Goesele's angle weight ranks a near neighbour low (a short baseline gives imprecise
    // depths), but where the neighbour is the only other view -- the edges of a capture, a
    // surface seen from one side -- any depth beats none, which is what fusion's consistency
    // test then judges.
    if (options.coverage_source && !chosen.empty()) {
      std::map<image_t, int> uncovered;
      for (const Contribution& c : list)
        if (covered[c.point] == 0) ++uncovered[c.source];
      image_t best = kInvalidImageId;
      int best_count = options.min_shared_points - 1;
      for (const auto& [source, count] : uncovered)  // ascending ids: ties go to the lower id
        if (count > best_count) best = source, best_count = count;
      if (best != kInvalidImageId) chosen.push_back(best);
    }
    if (!chosen.empty()) sources[reference] = std::move(chosen);
  }
  return sources;
}

std::vector<std::vector<uint32_t>> OverlappingViews(const Reconstruction& rec,
                                                    const std::vector<image_t>& views,
                                                    int max_views) {
  const uint32_t n = static_cast<uint32_t>(views.size());
  std::vector<std::vector<uint32_t>> out(n);
  if (n <= static_cast<uint32_t>(max_views) + 1) {
    for (uint32_t v = 0; v < n; ++v)
      for (uint32_t u = 0; u < n; ++u)
        if (u != v) out[v].push_back(u);
    return out;
  }
  std::unordered_map<image_t, uint32_t> index;
  for (uint32_t i = 0; i < n; ++i) index[views[i]] = i;
  std::vector<std::unordered_map<uint32_t, int>> shared(n);
  std::vector<uint32_t> in_track;
  for (const auto& [id, point] : rec.points3D()) {
    in_track.clear();
    for (const image_t s : RegisteredViews(rec, point))
      if (const auto it = index.find(s); it != index.end()) in_track.push_back(it->second);
    for (const uint32_t a : in_track)
      for (const uint32_t b : in_track)
        if (a != b) ++shared[a][b];
  }
  std::vector<std::pair<int, uint32_t>> ranked;  // (-shared points, index): best first
  for (uint32_t v = 0; v < n; ++v) {
    ranked.clear();
    for (const auto& [u, count] : shared[v]) ranked.push_back({-count, u});
    // Views that share no point rank last, in index order, where too few share any.
    for (uint32_t u = 0; u < n && ranked.size() < static_cast<size_t>(max_views); ++u)
      if (u != v && !shared[v].count(u)) ranked.push_back({0, u});
    const size_t keep = std::min(ranked.size(), static_cast<size_t>(max_views));
    std::partial_sort(ranked.begin(), ranked.begin() + keep, ranked.end());
    for (size_t k = 0; k < keep; ++k) out[v].push_back(ranked[k].second);
    std::sort(out[v].begin(), out[v].end());
  }
  return out;
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
  CheckAtLeast("source view covered_views", covered_views, 1);
  CheckInRange("--dense-redundant-weight", redundant_point_weight, 0.0, 1.0);
  CheckInRange("--dense-depth-range-percentile", depth_range_percentile, 0.0, 25.0);
}

}  // namespace varsfm
