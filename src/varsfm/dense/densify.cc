#include "varsfm/dense/densify.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>
#include <set>

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <Eigen/Cholesky>
#include <opencv2/imgproc.hpp>

#include "varsfm/dense/source_views.h"
#include "varsfm/geometry/fundamental.h"
#include "varsfm/geometry/triangulation.h"
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"
#include "varsfm/util/option_check.h"
#include "varsfm/util/progress.h"
#include "varsfm/util/timer.h"

namespace varsfm {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

// A registered view prepared for matching: its undistorted image and pinhole projection.
struct DenseView {
  image_t image_id = kInvalidImageId;
  UndistortedView image;
  Matrix34d P;  // K [R | t] of the matching image
  Rigid3d cam_from_world;
  Eigen::Vector3d center;
};

// A triangulated quasi-dense match of one pair.
struct PairPoint {
  Eigen::Vector3d xyz;
  Eigen::Vector2f x1, x2;
  Eigen::Vector3f color;  // BGR
};

// The registered views that see each 3D point, grouped per image pair (first < second).
std::map<std::pair<image_t, image_t>, std::vector<point3D_t>> SharedPoints(
    const Reconstruction& rec) {
  std::map<std::pair<image_t, image_t>, std::vector<point3D_t>> shared;
  for (const auto& [id, point] : rec.points3D()) {
    const std::vector<image_t> views = RegisteredViews(rec, point);
    for (size_t a = 0; a < views.size(); ++a)
      for (size_t b = a + 1; b < views.size(); ++b) shared[{views[a], views[b]}].push_back(id);
  }
  return shared;
}

Eigen::Vector3d ProjectH(const Matrix34d& P, const Eigen::Vector3d& X) {
  return P * X.homogeneous();
}

cv::Vec3f SampleColor(const cv::Mat& color, const Eigen::Vector2f& x) {
  const int c = std::clamp(static_cast<int>(x.x()), 0, color.cols - 1);
  const int r = std::clamp(static_cast<int>(x.y()), 0, color.rows - 1);
  const cv::Vec3b v = color.at<cv::Vec3b>(r, c);
  return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])};
}

// Linear triangulation of a match in two pinhole views: the inhomogeneous form (X = (X, 1)) of
// the DLT of Hartley & Zisserman section 12.2, solved by its 3x3 normal equations and solved
// again with each view's rows divided by the point's projective depth there, so the algebraic
// residuals become pixel residuals (the iterative linear method of Hartley & Sturm, "Triangu-
// lation", CVIU 1997, one iteration). It replaces an SVD of the 4x4 homogeneous system, which
// took a fifth of densify's time for millions of matches. False: at infinity or behind a view.
bool TriangulateMatch(const Matrix34d& P1, const Matrix34d& P2, const Eigen::Vector2d& x1,
                      const Eigen::Vector2d& x2, Eigen::Vector3d* X) {
  Eigen::Matrix4d A;
  A.row(0) = x1.x() * P1.row(2) - P1.row(0);
  A.row(1) = x1.y() * P1.row(2) - P1.row(1);
  A.row(2) = x2.x() * P2.row(2) - P2.row(0);
  A.row(3) = x2.y() * P2.row(2) - P2.row(1);
  double w1 = 1, w2 = 1;
  for (int iteration = 0; iteration < 2; ++iteration) {
    Eigen::Matrix4d B = A;
    B.topRows<2>() /= w1;
    B.bottomRows<2>() /= w2;
    const Eigen::Matrix3d N = B.leftCols<3>().transpose() * B.leftCols<3>();
    const Eigen::Vector3d rhs = -B.leftCols<3>().transpose() * B.col(3);
    const Eigen::LLT<Eigen::Matrix3d> llt(N);
    if (llt.info() != Eigen::Success) return false;
    *X = llt.solve(rhs);
    if (!X->allFinite()) return false;
    w1 = P1.row(2).dot(X->homogeneous());
    w2 = P2.row(2).dot(X->homogeneous());
    if (w1 <= 0 || w2 <= 0) return false;
  }
  return true;
}

// Propagation and triangulation of one pair (views a, b), seeded by their shared sparse points.
std::vector<PairPoint> DensifyPair(const Reconstruction& rec, const DenseView& a,
                                   const DenseView& b, const std::vector<point3D_t>& shared,
                                   const DenseReconstructionOptions& options, size_t* num_matches) {
  std::vector<SeedMatch> seeds;
  const auto in_image = [](const UndistortedView& v, const Eigen::Vector3d& h, Eigen::Vector2d* x) {
    if (h.z() <= 0) return false;
    *x = h.hnormalized();
    return x->x() >= 0 && x->y() >= 0 && x->x() < v.gray.cols && x->y() < v.gray.rows;
  };
  for (point3D_t id : shared) {
    const Eigen::Vector3d& X = rec.point3D(id).xyz;
    SeedMatch s;
    if (in_image(a.image, ProjectH(a.P, X), &s.x1) && in_image(b.image, ProjectH(b.P, X), &s.x2))
      seeds.push_back(s);
  }
  std::optional<Eigen::Matrix3d> F;
  if (options.use_epipolar_constraint)
    F = FundamentalFromPose(a.image.K, b.image.K, b.cam_from_world * a.cam_from_world.Inverse());
  const std::vector<QuasiDenseMatch> matches =
      PropagateMatches(a.image.gray, b.image.gray, seeds, options.propagation, F);
  *num_matches = matches.size();

  std::vector<PairPoint> points;
  points.reserve(matches.size());
  const double min_angle = options.min_point_angle_deg * kDegToRad;
  const double max_err2 = options.max_reprojection_error * options.max_reprojection_error;
  for (const QuasiDenseMatch& m : matches) {
    const Eigen::Vector2d x1 = m.x1.cast<double>(), x2 = m.x2.cast<double>();
    Eigen::Vector3d X;
    if (!TriangulateMatch(a.P, b.P, x1, x2, &X)) continue;
    const Eigen::Vector3d h1 = ProjectH(a.P, X), h2 = ProjectH(b.P, X);
    if (h1.z() <= 0 || h2.z() <= 0) continue;
    if ((h1.hnormalized() - x1).squaredNorm() > max_err2 ||
        (h2.hnormalized() - x2).squaredNorm() > max_err2)
      continue;
    if (TriangulationAngle(a.center, b.center, X) < min_angle) continue;
    const cv::Vec3f c =
        0.5f * (SampleColor(a.image.color, m.x1) + SampleColor(b.image.color, m.x2));
    points.push_back({X, m.x1, m.x2, Eigen::Vector3f(c[0], c[1], c[2])});
  }
  return points;
}

// Fusion across pairs (sequential in pair order, so deterministic): a new point merges with the
// point already owning the pixel it projects to in a nearby view when their depths agree; each
// point claims the pixels of the two views it was matched in.
struct Fusion {
  struct Observation {
    uint32_t point;
    uint32_t view;
    Eigen::Vector2f pixel;
  };
  std::vector<Eigen::Vector3d> sum;
  std::vector<Eigen::Vector3f> color_sum;
  std::vector<uint32_t> count;
  std::vector<Observation> observations;
  std::vector<std::vector<int32_t>> owner;  // per view, per pixel: fused point or -1

  explicit Fusion(const std::vector<DenseView>& views) {
    for (const DenseView& v : views) owner.emplace_back(v.image.gray.total(), -1);
  }

  void Add(const std::vector<DenseView>& views, const std::vector<uint32_t>& check_views,
           uint32_t va, uint32_t vb, const PairPoint& p, double depth_tolerance) {
    int32_t target = -1;
    for (uint32_t v : check_views) {
      const Eigen::Vector3d h = ProjectH(views[v].P, p.xyz);
      if (h.z() <= 0) continue;
      const Eigen::Vector2d x = h.hnormalized();
      const cv::Mat& g = views[v].image.gray;
      if (x.x() < 0 || x.y() < 0 || x.x() >= g.cols || x.y() >= g.rows) continue;
      const int32_t o = owner[v][static_cast<size_t>(x.y()) * g.cols + static_cast<size_t>(x.x())];
      if (o < 0) continue;
      const double depth = ProjectH(views[v].P, sum[o] / count[o]).z();
      if (std::abs(depth - h.z()) <= depth_tolerance * h.z()) {
        target = o;
        break;
      }
    }
    if (target < 0) {
      target = static_cast<int32_t>(sum.size());
      sum.push_back(Eigen::Vector3d::Zero());
      color_sum.push_back(Eigen::Vector3f::Zero());
      count.push_back(0);
    }
    sum[target] += p.xyz;
    color_sum[target] += p.color;
    ++count[target];
    const uint32_t t = static_cast<uint32_t>(target);
    observations.push_back({t, va, p.x1});
    observations.push_back({t, vb, p.x2});
    Claim(views, va, p.x1, target);
    Claim(views, vb, p.x2, target);
  }

  void Claim(const std::vector<DenseView>& views, uint32_t v, const Eigen::Vector2f& x,
             int32_t point) {
    const size_t i =
        static_cast<size_t>(x.y()) * views[v].image.gray.cols + static_cast<size_t>(x.x());
    if (i < owner[v].size() && owner[v][i] < 0) owner[v][i] = point;
  }
};

}  // namespace

std::vector<std::pair<image_t, image_t>> SelectDensePairs(
    const Reconstruction& rec, const DenseReconstructionOptions& options) {
  const auto shared = SharedPoints(rec);
  // Candidate partners per image: (shared count, partner).
  std::map<image_t, std::vector<std::pair<size_t, image_t>>> candidates;
  for (const auto& [pair, ids] : shared) {
    if (ids.size() < static_cast<size_t>(options.min_shared_points)) continue;
    const Eigen::Vector3d c1 = rec.image(pair.first).Center(), c2 = rec.image(pair.second).Center();
    std::vector<double> angles;
    const size_t step = std::max<size_t>(1, ids.size() / 200);
    for (size_t i = 0; i < ids.size(); i += step)
      angles.push_back(TriangulationAngle(c1, c2, rec.point3D(ids[i]).xyz));
    std::nth_element(angles.begin(), angles.begin() + angles.size() / 2, angles.end());
    const double median = angles[angles.size() / 2] / kDegToRad;
    if (median < options.min_pair_angle_deg || median > options.max_pair_angle_deg) continue;
    candidates[pair.first].push_back({ids.size(), pair.second});
    candidates[pair.second].push_back({ids.size(), pair.first});
  }
  std::set<std::pair<image_t, image_t>> pairs;
  for (auto& [image, partners] : candidates) {
    std::sort(partners.begin(), partners.end(), [](const auto& x, const auto& y) {
      return x.first != y.first ? x.first > y.first : x.second < y.second;
    });
    for (size_t i = 0; i < partners.size() && i < static_cast<size_t>(options.max_partners); ++i)
      pairs.insert({std::min(image, partners[i].second), std::max(image, partners[i].second)});
  }
  return {pairs.begin(), pairs.end()};
}

namespace {

PointCloud DensifyByPropagation(const Reconstruction& rec,
                                const std::function<cv::Mat(image_t)>& load_image,
                                const DenseReconstructionOptions& options, DensifyStats& st,
                                DenseVisibility* visibility) {
  const auto pairs = SelectDensePairs(rec, options);
  if (pairs.empty())
    Fail("densify: no image pair shares {} points with a triangulation angle of {}..{} deg",
         options.min_shared_points, options.min_pair_angle_deg, options.max_pair_angle_deg);
  st.num_pairs = pairs.size();

  // Views involved in a pair, each loaded and undistorted once.
  std::set<image_t> used;
  for (const auto& [i, j] : pairs) used.insert(i), used.insert(j);
  std::vector<DenseView> views;
  std::map<image_t, uint32_t> view_index;
  for (image_t id : used) {
    view_index[id] = static_cast<uint32_t>(views.size());
    views.push_back({});
    views.back().image_id = id;
  }
  Timer timer;
  {
    Progress progress("undistort", views.size());
    tbb::parallel_for(size_t{0}, views.size(), [&](size_t i) {
      DenseView& v = views[i];
      v.image = UndistortAtMostSize(load_image(v.image_id), rec.CameraOf(v.image_id),
                                    options.max_image_size);
      v.cam_from_world = rec.image(v.image_id).cam_from_world;
      v.center = v.cam_from_world.Center();
      v.P = v.image.K * v.cam_from_world.ToMatrix();
      progress.Tick();
    });
  }
  st.seconds_undistort = timer.Seconds();
  timer.Restart();

  const auto shared = SharedPoints(rec);
  std::vector<std::vector<PairPoint>> pair_points(pairs.size());
  std::vector<size_t> pair_matches(pairs.size(), 0);
  {
    Progress progress("propagate", pairs.size());
    tbb::parallel_for(size_t{0}, pairs.size(), [&](size_t p) {
      const auto& [i, j] = pairs[p];
      pair_points[p] = DensifyPair(rec, views[view_index.at(i)], views[view_index.at(j)],
                                   shared.at(pairs[p]), options, &pair_matches[p]);
      progress.Tick(1, fmt::format("{} pts", pair_points[p].size()));
    });
  }
  st.seconds_propagation = timer.Seconds();
  timer.Restart();
  for (size_t p = 0; p < pairs.size(); ++p)
    st.num_matches += pair_matches[p], st.num_triangulated += pair_points[p].size();

  // Views checked for a pair's points: its own two and their partners in other pairs.
  std::vector<std::set<uint32_t>> adjacent(views.size());
  for (const auto& [i, j] : pairs) {
    const uint32_t a = view_index.at(i), b = view_index.at(j);
    adjacent[a].insert({a, b}), adjacent[b].insert({a, b});
  }
  Fusion fusion(views);
  fusion.observations.reserve(2 * st.num_triangulated);
  for (size_t p = 0; p < pairs.size(); ++p) {
    const uint32_t a = view_index.at(pairs[p].first), b = view_index.at(pairs[p].second);
    std::set<uint32_t> check(adjacent[a]);
    check.insert(adjacent[b].begin(), adjacent[b].end());
    const std::vector<uint32_t> check_views(check.begin(), check.end());
    for (const PairPoint& point : pair_points[p])
      fusion.Add(views, check_views, a, b, point, options.fusion_depth_tolerance);
    pair_points[p] = {};
  }

  // Every observation of a fused point must still reproject within the tolerance (twice the
  // per-pair one: merged positions are averages of points up to a pixel and a depth step apart).
  const size_t n = fusion.sum.size();
  std::vector<uint32_t> valid(n, 0);
  std::vector<uint32_t> first_view(n, UINT32_MAX);
  std::vector<std::vector<uint32_t>> seen_views(n);  // the views of the valid observations
  const double max_err2 = 4 * options.max_reprojection_error * options.max_reprojection_error;
  std::vector<std::vector<image_t>> seen_by(visibility ? n : 0);
  for (const auto& obs : fusion.observations) {
    const Eigen::Vector3d X = fusion.sum[obs.point] / fusion.count[obs.point];
    const Eigen::Vector3d h = ProjectH(views[obs.view].P, X);
    if (h.z() <= 0 || (h.hnormalized() - obs.pixel.cast<double>()).squaredNorm() > max_err2)
      continue;
    ++valid[obs.point];
    if (first_view[obs.point] == UINT32_MAX) first_view[obs.point] = obs.view;
    if (visibility) seen_by[obs.point].push_back(views[obs.view].image_id);
    seen_views[obs.point].push_back(obs.view);
  }
  if (visibility) visibility->clear();
  // Visibility for surfaces that carve free space along the rays (mesh/delaunay_surface.h):
  // every view of the sequence is a viewpoint, each point lists those it was matched in.
  PointCloud cloud;
  for (const DenseView& v : views) cloud.viewpoints.push_back(v.center);
  std::vector<Eigen::Vector3d> centers;
  std::vector<double> footprints;  // size of a matching pixel at the point (for the normals)
  for (size_t i = 0; i < n; ++i) {
    if (valid[i] < static_cast<uint32_t>(options.min_views)) continue;
    if (visibility) {
      std::vector<image_t>& ids = seen_by[i];
      std::sort(ids.begin(), ids.end());
      ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
      visibility->push_back(std::move(ids));
    }
    const Eigen::Vector3d X = fusion.sum[i] / fusion.count[i];
    const Eigen::Vector3f c = fusion.color_sum[i] / static_cast<float>(fusion.count[i]);
    cloud.points.push_back(X);
    std::vector<uint32_t>& seen = cloud.visibility.emplace_back(std::move(seen_views[i]));
    std::sort(seen.begin(), seen.end());
    seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
    if (seen.size() > 255) seen.resize(255);  // the PLY list's count is a byte
    // BGR -> RGB.
    cloud.colors.push_back({static_cast<uint8_t>(std::lround(c.z())),
                            static_cast<uint8_t>(std::lround(c.y())),
                            static_cast<uint8_t>(std::lround(c.x()))});
    const DenseView& v = views[first_view[i]];
    centers.push_back(v.center);
    footprints.push_back(ProjectH(v.P, X).z() / v.image.K(0, 0));
  }
  if (cloud.points.empty()) Fail("densify: no dense point survived the filters");
  st.seconds_fusion = timer.Seconds();
  timer.Restart();
  std::nth_element(footprints.begin(), footprints.begin() + footprints.size() / 2,
                   footprints.end());
  cloud.normals = EstimateNormals(cloud.points, centers, options.normal_neighbors,
                                  footprints[footprints.size() / 2]);
  st.num_points = cloud.points.size();
  st.seconds_normals = timer.Seconds();
  info(
      "densify: {} pairs, {} matches, {} triangulated, {} fused points (undistort {:.1f} s, "
      "propagation {:.1f} s, fusion {:.1f} s, normals {:.1f} s)",
      st.num_pairs, st.num_matches, st.num_triangulated, st.num_points, st.seconds_undistort,
      st.seconds_propagation, st.seconds_fusion, st.seconds_normals);
  return cloud;
}

// Appends b (and its visibility) to a.
void Append(PointCloud&& b, DenseVisibility&& b_visibility, PointCloud* a,
            DenseVisibility* a_visibility) {
  a->points.insert(a->points.end(), b.points.begin(), b.points.end());
  a->normals.insert(a->normals.end(), b.normals.begin(), b.normals.end());
  a->colors.insert(a->colors.end(), b.colors.begin(), b.colors.end());
  if (a_visibility)
    for (auto& ids : b_visibility) a_visibility->push_back(std::move(ids));
}

// The checks and the thread limit every densification starts with; the limit lasts as long as
// `threads`.
void StartDensify(const Reconstruction& rec, const DenseReconstructionOptions& options,
                  std::optional<tbb::global_control>* threads) {
  if (rec.NumRegisteredImages() < 2)
    Fail("densify: the sparse model has {} registered images; at least 2 are needed",
         rec.NumRegisteredImages());
  if (options.num_threads > 0)
    threads->emplace(tbb::global_control::max_allowed_parallelism, options.num_threads);
}

}  // namespace

void DensifyInto(const Reconstruction& rec, const std::function<cv::Mat(image_t)>& load_image,
                 const DenseReconstructionOptions& options, DensifyStats* stats,
                 const FusedPointSink& sink) {
  if (!StreamsPoints(options.method))
    Fail("densify: the {} method's points cannot be streamed",
         NameOf(kDenseMethodNames, options.method));
  std::optional<tbb::global_control> threads;
  StartDensify(rec, options, &threads);
  DensifyStats local;
  DensifyStats& st = stats ? *stats : local;
  st = {};
  MultiViewStereoInto(rec, load_image, options.mvs, {}, sink, &st.mvs);
}

PointCloud Densify(const Reconstruction& rec, const std::function<cv::Mat(image_t)>& load_image,
                   const DenseReconstructionOptions& options, DensifyStats* stats,
                   DenseVisibility* visibility) {
  std::optional<tbb::global_control> threads;
  StartDensify(rec, options, &threads);
  DensifyStats local;
  DensifyStats& st = stats ? *stats : local;
  st = {};
  if (options.method == DenseMethod::kPatchMatch)
    return MultiViewStereo(rec, load_image, options.mvs, {}, visibility, &st.mvs);
  PointCloud cloud = DensifyByPropagation(rec, load_image, options, st, visibility);
  if (options.method == DenseMethod::kPropagation) return cloud;
  // The cloud's own visibility (viewpoints and indices, mesh/delaunay_surface.h) is recorded by
  // propagation only; a cloud that PatchMatch's points join goes without it.
  cloud.visibility.clear();
  cloud.viewpoints.clear();
  MultiViewStereoInputs inputs;
  if (options.method == DenseMethod::kSeeded || options.method == DenseMethod::kSeededFill)
    inputs.prior = &cloud;
  if (options.method == DenseMethod::kFill || options.method == DenseMethod::kSeededFill)
    inputs.covered = &cloud;
  DenseVisibility mvs_visibility;
  PointCloud mvs = MultiViewStereo(rec, load_image, options.mvs, inputs,
                                   visibility ? &mvs_visibility : nullptr, &st.mvs);
  if (options.method == DenseMethod::kSeeded) {
    if (visibility) *visibility = std::move(mvs_visibility);
    return mvs;
  }
  Append(std::move(mvs), std::move(mvs_visibility), &cloud, visibility);
  return cloud;
}

void DenseReconstructionOptions::Check() const {
  mvs.Check();  // also for propagation: a bad value is refused, not silently ignored
  CheckInRange("--partners", max_partners, 1, 10);
  CheckAtLeast("min_shared_points", min_shared_points, 1);
  CheckInRange("min_pair_angle_deg", min_pair_angle_deg, 0, 180);
  CheckInRange("max_pair_angle_deg", max_pair_angle_deg, min_pair_angle_deg, 180.0);
  CheckAtLeast("--max-image-size", max_image_size, 16);
  propagation.Check();
  CheckInRange("min_point_angle_deg", min_point_angle_deg, 0, 180);
  CheckPositive("max_reprojection_error", max_reprojection_error);
  CheckNonNegative("fusion_depth_tolerance", fusion_depth_tolerance);
  CheckAtLeast("min_views", min_views, 2);
  CheckAtLeast("normal_neighbors", normal_neighbors, 3);
  CheckNonNegative("--threads", num_threads);
}

}  // namespace varsfm
