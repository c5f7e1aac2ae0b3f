#include "varsfm/sfm/incremental_mapper.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <set>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "varsfm/ba/bundle_adjuster.h"
#include "varsfm/calibration/two_view_calibration.h"
#include "varsfm/estimators/projection_estimator.h"
#include "varsfm/estimators/two_view_estimators.h"
#include "varsfm/geometry/projection_decomposition.h"
#include "varsfm/geometry/triangulation.h"
#include "varsfm/sfm/absolute_pose_refinement.h"
#include "varsfm/util/log.h"
#include "varsfm/util/timer.h"

namespace varsfm {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

// The intrinsics the bundle adjustments refine, from the mapper's policy. Parameters shared
// per image size are estimated in the adjustments of the whole model (`whole_model`: two-view
// and global; groups need min_images_to_share images, so the two-view one holds them) and held
// at their current values in local ones and in the registration of a new image, so that every
// camera of a size keeps the same values.
IntrinsicsOptions MapperIntrinsics(const IncrementalMapperOptions& o, bool whole_model) {
  IntrinsicsOptions in;
  in.refine_focal = true;
  in.refine_aspect = o.refine_aspect;
  in.refine_skew = o.refine_skew;
  in.refine_principal_point = o.refine_principal_point;
  in.refine_k1 = o.refine_distortion;
  in.refine_k2 = o.refine_distortion;
  const bool share_pp = o.share_principal_point || o.share_all_but_focal;
  if (o.share_all_but_focal)
    in.shared_per_size = {Camera::kAspect, Camera::kSkew, Camera::kU0,
                          Camera::kV0,     Camera::kK1,   Camera::kK2};
  else if (share_pp && !o.refine_principal_point)
    in.shared_per_size = {Camera::kU0, Camera::kV0};
  if (o.share_principal_point && !o.refine_principal_point) in.refine_principal_point = whole_model;
  if (!whole_model)
    for (const int i : in.shared_per_size) {
      if (i == Camera::kAspect) in.refine_aspect = false;
      if (i == Camera::kSkew) in.refine_skew = false;
      if (i == Camera::kU0) in.refine_principal_point = false;
      if (i == Camera::kK1) in.refine_k1 = false;
      if (i == Camera::kK2) in.refine_k2 = false;
    }
  return in;
}

// Whether a K from the DLT decomposition is physically plausible for this image.
bool PlausibleCalibration(const Eigen::Matrix3d& K, const Camera& camera) {
  const double size = std::max(camera.width, camera.height);
  const double f = K(0, 0);
  const double aspect = K(1, 1) / K(0, 0);
  const Eigen::Vector2d pp(K(0, 2), K(1, 2));
  const Eigen::Vector2d centre(camera.width / 2.0, camera.height / 2.0);
  return f > 0.3 * size && f < 5 * size && aspect > 0.8 && aspect < 1.25 &&
         std::abs(K(0, 1)) < 0.1 * f && (pp - centre).norm() < 0.3 * size;
}

double MedianTriangulationAngle(const Reconstruction& rec) {
  std::vector<double> angles;
  for (const auto& [id, point] : rec.points3D()) {
    if (point.track.size() < 2) continue;
    angles.push_back(TriangulationAngle(rec.image(point.track[0].image_id).Center(),
                                        rec.image(point.track[1].image_id).Center(), point.xyz));
  }
  if (angles.empty()) return 0;
  std::nth_element(angles.begin(), angles.begin() + angles.size() / 2, angles.end());
  return angles[angles.size() / 2];
}

// Inlier count of a pose+camera on the 2D-3D correspondences.
size_t CountInliers(const Camera& camera, const Rigid3d& pose,
                    const std::vector<Eigen::Vector2d>& x, const std::vector<Eigen::Vector3d>& X,
                    double max_error) {
  size_t n = 0;
  for (size_t i = 0; i < x.size(); ++i)
    if (ReprojectionError(camera, pose, x[i], X[i]) <= max_error) ++n;
  return n;
}

}  // namespace

IncrementalMapper::IncrementalMapper(const CorrespondenceGraph& graph,
                                     std::vector<std::pair<image_t, image_t>> excluded,
                                     IncrementalMapperOptions options)
    : graph_(graph), excluded_initial_pairs_(std::move(excluded)), options_(std::move(options)) {}

MapperSummary IncrementalMapper::Reconstruct(Reconstruction* rec) {
  MapperSummary summary;
  summary.num_images = rec->images().size();
  registration_order_.clear();
  frontier_.clear();

  // 1. Initialisation: candidates by the disparity criterion; the first pair whose
  // self-calibration is not degenerate wins, else the best degenerate one (prior focal).
  Timer timer;
  const auto candidates =
      RankInitialPairs(*rec, graph_, excluded_initial_pairs_, options_.initial_pair);
  if (candidates.empty()) {
    summary.message = NoInitialPairReason(graph_, excluded_initial_pairs_, options_.initial_pair);
    return summary;
  }
  // Cheap first pass: F and the conditioning of the closed-form focal lengths for the best
  // candidates; then full calibration of well-conditioned pairs first, in score order.
  const Reconstruction empty = *rec;
  const int trials = std::min<int>(options_.max_initial_pair_trials, candidates.size());
  std::vector<PairGeometry> geometries;
  for (int k = 0; k < trials; ++k) geometries.push_back(EstimatePairGeometry(*rec, candidates[k]));
  // Pass 1: well-conditioned pairs whose calibration is not flagged; pass 2: any pair.
  bool initialized = false;
  int initial = -1;
  for (const bool first_pass : {true, false}) {
    for (int k = 0; k < trials && !initialized; ++k) {
      if (!geometries[k].success || (first_pass && !geometries[k].well_conditioned)) continue;
      *rec = empty;
      initialized = Initialize(rec, candidates[k], geometries[k],
                               /*accept_degenerate=*/!first_pass, &summary);
      initial = k;
    }
  }
  if (initialized && summary.initial_focal_from_prior && options_.degenerate_init_focal_search)
    SelectDegenerateFocal(empty, candidates[initial], geometries[initial], rec, &summary);
  if (!initialized) {
    *rec = empty;
    summary.message =
        "no image pair could be initialised (too little parallax, or matches explained "
        "by a rotation or a plane)";
    return summary;
  }
  summary.seconds_initialization = timer.Seconds();
  if (options_.progress) options_.progress(2, summary.num_images, rec->RmsReprojectionError());

  // 2. Register the other images one by one; failed ones are retried after later successes.
  size_t last_global_size = 2;
  bool first_global_done = false;
  double progress_rms = -1.0;
  while (true) {
    bool registered_any = false;
    for (const image_t image_id : NextImageCandidates(*rec)) {
      Timer reg_timer;
      const bool ok = RegisterImage(rec, image_id);
      summary.seconds_registration += reg_timer.Seconds();
      if (!ok) continue;
      registration_order_.push_back(image_id);
      Timer tri_timer;
      TriangulateImage(rec, image_id);
      summary.seconds_triangulation += tri_timer.Seconds();

      const size_t n = rec->NumRegisteredImages();
      // M0 <= 0: a global BA after every image (the Pollefeys-like baseline of the paper).
      const bool paper_global =
          options_.first_global_ba_images <= 0 ||
          (!first_global_done && n >= static_cast<size_t>(options_.first_global_ba_images));
      // A growth adjustment is skipped when the final one follows within half a growth step
      // (all images registered before the model grows by the factor's square root): it would
      // redo nearly the same problem (e.g. at 192 of 200 images). Not within a whole step: on
      // a 1000-image sequence that skipped the one due at 808 images, and the final one had to
      // fix the drift of ~420 images with local adjustments only (44 iterations, 143 s).
      const bool final_within_growth =
          options_.final_global_ba &&
          summary.num_images < std::sqrt(options_.global_ba_growth) * static_cast<double>(n);
      const bool growth_global = first_global_done && options_.global_ba_growth > 1.0 &&
                                 n >= options_.global_ba_growth * last_global_size &&
                                 !final_within_growth;
      // A degenerate initial pair entered with its focal lengths held (Initialize): one early
      // global adjustment, once the images determine them, settles every focal length before
      // the model grows on them (fountain-P11-zoom: the final adjustment then needs 8
      // iterations instead of 50).
      const bool settle_focals =
          summary.initial_calibration_degenerate && options_.degenerate_init_global_ba_images > 0 &&
          n == static_cast<size_t>(options_.degenerate_init_global_ba_images);
      if (paper_global || growth_global) {
        GlobalBundleAdjustment(rec, &summary, /*retriangulate=*/true,
                               options_.global_ba_max_iterations,
                               paper_global ? options_.global_ba_function_tolerance
                                            : options_.growth_ba_function_tolerance);
        first_global_done = true;
        last_global_size = n;
      } else if (settle_focals) {  // outside the schedule: M0 and the growth stay as they are
        GlobalBundleAdjustment(rec, &summary, /*retriangulate=*/true,
                               options_.global_ba_max_iterations,
                               options_.global_ba_function_tolerance);
      } else {
        LocalBundleAdjustment(rec, &summary);
      }
      if (options_.progress) {
        // The model's RMS costs a pass over every observation: refreshed 20 times a run, so
        // that reporting stays linear in the number of images.
        const size_t every = std::max<size_t>(1, summary.num_images / 20);
        if (n % every == 0 || n == summary.num_images || progress_rms < 0)
          progress_rms = rec->RmsReprojectionError();
        options_.progress(n, summary.num_images, progress_rms);
      }
      registered_any = true;
      break;  // candidates change with every registration
    }
    if (!registered_any) break;
  }

  // 3. Final global adjustment (with re-triangulation and filtering).
  if (options_.final_global_ba)
    GlobalBundleAdjustment(rec, &summary, /*retriangulate=*/true,
                           options_.final_global_ba_max_iterations,
                           options_.global_ba_function_tolerance);
  rec->UpdatePointErrors();
  summary.num_registered = rec->NumRegisteredImages();
  summary.success = true;
  return summary;
}

IncrementalMapper::PairGeometry IncrementalMapper::EstimatePairGeometry(
    const Reconstruction& rec, const InitialPairCandidate& pair) const {
  PairGeometry geometry;
  const FeatureMatches matches = graph_.MatchesBetween(pair.image_id1, pair.image_id2);
  std::vector<Eigen::Vector2d> x1, x2;
  for (const auto& m : matches) {
    x1.push_back(rec.image(pair.image_id1).points2D[m.point2D_idx1].xy);
    x2.push_back(rec.image(pair.image_id2).points2D[m.point2D_idx2].xy);
  }
  // F re-estimated on the verified matches with a tight threshold.
  RansacOptions ransac;
  ransac.max_error = 1.5;
  ransac.seed = DeriveSeed(options_.seed, pair.image_id1 * 65536ull + pair.image_id2);
  const auto report = EstimateFundamentalMatrix(x1, x2, ransac);
  if (!report.success) return geometry;
  geometry.success = true;
  geometry.F = report.model;
  for (size_t i = 0; i < matches.size(); ++i)
    if (report.inlier_mask[i]) geometry.inlier_matches.push_back(matches[i]);
  const Camera& c1 = rec.CameraOf(pair.image_id1);
  const Camera& c2 = rec.CameraOf(pair.image_id2);
  geometry.well_conditioned =
      ClosedFormFocalsWellConditioned(geometry.F, c1.width, c1.height, c2.width, c2.height);
  return geometry;
}

bool IncrementalMapper::Initialize(Reconstruction* rec, const InitialPairCandidate& pair,
                                   const PairGeometry& geometry, bool accept_degenerate,
                                   MapperSummary* summary, double focal_scale, bool adjust) {
  const image_t id1 = pair.image_id1, id2 = pair.image_id2;
  const FeatureMatches& inlier_matches = geometry.inlier_matches;
  std::vector<Eigen::Vector2d> in1, in2;
  for (const auto& m : inlier_matches) {
    in1.push_back(rec->image(id1).points2D[m.point2D_idx1].xy);
    in2.push_back(rec->image(id2).points2D[m.point2D_idx2].xy);
  }

  Camera& camera1 = rec->CameraOf(id1);
  Camera& camera2 = rec->CameraOf(id2);
  TwoViewCalibrationOptions calib_options;
  // Two views cannot separate k1, k2 from the focal lengths well (tests/calibration): the
  // distortion is estimated once more views are in.
  calib_options.refine_distortion = false;
  calib_options.num_threads = options_.num_threads;
  // The workspace's focal lengths are the priors (EXIF, else the extraction's fallback factor x
  // the larger image side): a degenerate pair keeps them.
  calib_options.prior_focal1 = focal_scale * camera1.focal();
  calib_options.prior_focal2 = focal_scale * camera2.focal();
  const TwoViewCalibration calib =
      CalibrateTwoView(in1, in2, camera1.width, camera1.height, camera2.width, camera2.height,
                       geometry.F, calib_options);
  if (!calib.success) return false;
  debug("initial pair {} {}: f1 {:.1f} f2 {:.1f} degenerate {} ({})", id1, id2,
        calib.camera1.focal(), calib.camera2.focal(), calib.degenerate, calib.degeneracy_reason);
  if (calib.degenerate && !accept_degenerate) return false;

  const bool shared = rec->image(id1).camera_id == rec->image(id2).camera_id;
  camera1.params = calib.camera1.params;
  if (!shared) camera2.params = calib.camera2.params;
  rec->image(id1).cam_from_world = Rigid3d();
  rec->image(id2).cam_from_world = calib.cam2_from_cam1;
  rec->RegisterImage(id1);
  rec->RegisterImage(id2);
  ExtendFrontier(id1);
  ExtendFrontier(id2);
  for (size_t i = 0; i < inlier_matches.size(); ++i) {
    if (!calib.point_valid[i]) continue;
    rec->AddPoint3D(calib.points[i],
                    {{id1, inlier_matches[i].point2D_idx1}, {id2, inlier_matches[i].point2D_idx2}});
  }
  if (rec->points3D().size() < static_cast<size_t>(options_.min_initial_points)) return false;
  if (MedianTriangulationAngle(*rec) < options_.init_min_median_angle_deg * kDegree) {
    debug("initial pair {} {}: too little parallax", id1, id2);
    return false;
  }

  // Two-view bundle adjustment (eq. 34) with the mapper's intrinsics policy; the focal lengths
  // of a degenerate pair are held (two views do not determine them: left free, they drift along
  // the valley to wherever the solver's path ends; the global adjustment at 4 images frees them).
  if (adjust) {
    BundleAdjustmentOptions ba;
    ba.intrinsics = MapperIntrinsics(options_, /*whole_model=*/true);
    if (calib.degenerate) ba.intrinsics.refine_focal = false;
    ba.num_threads = options_.num_threads;
    ba.solver = options_.ba_solver;
    RunBundleAdjustment(ba, BundleAdjustmentConfig::Global(*rec), rec);
    rec->FilterObservationsWithLargeError(options_.filter_max_error_px);
    if (rec->points3D().size() < static_cast<size_t>(options_.min_initial_points)) return false;
  }

  summary->initial_image_id1 = id1;
  summary->initial_image_id2 = id2;
  summary->initial_calibration_degenerate = calib.degenerate;
  summary->initial_focal_from_prior = calib.focal_from_prior;
  summary->initial_focal_scale = focal_scale;
  registration_order_ = {id1, id2};
  return true;
}

void IncrementalMapper::ExtendFrontier(image_t registered) {
  if (!graph_.ExistsImage(registered)) return;
  for (const image_t id : graph_.NeighborsOf(registered)) frontier_.insert(id);
}

std::vector<image_t> IncrementalMapper::NextImageCandidates(const Reconstruction& rec) const {
  // Score: the number of the image's 2D points whose tracks reach a reconstructed 3D point.
  std::vector<std::pair<size_t, image_t>> scored;
  image_t last_registered = registration_order_.empty() ? 0 : registration_order_.back();
  for (const image_t image_id : frontier_) {
    if (!rec.ExistsImage(image_id)) continue;  // frontier_ holds graph images only
    const Image& image = rec.image(image_id);
    if (image.registered) continue;
    // Only images that match a registered one can see reconstructed points: on a sequence
    // that is the few next to the registered ones, and the scan below stays bounded.
    const auto& neighbors = graph_.NeighborsOf(image_id);
    if (std::none_of(neighbors.begin(), neighbors.end(),
                     [&rec](image_t id) { return rec.image(id).registered; }))
      continue;
    // For sequential input only the threshold matters (the order is the sequence's), and
    // the count stops there: counting all took 4 % of a 1000-image street's mapping.
    const size_t enough = options_.sequential_order
                              ? static_cast<size_t>(options_.min_correspondences)
                              : std::numeric_limits<size_t>::max();
    size_t visible = 0;
    for (point2D_t idx = 0; idx < image.points2D.size() && visible < enough; ++idx) {
      for (const auto& corr : graph_.CorrespondencesOf(image_id, idx)) {
        const Image& other = rec.image(corr.image_id);
        if (other.registered && other.points2D[corr.point2D_idx].HasPoint3D()) {
          ++visible;
          break;
        }
      }
    }
    if (visible < static_cast<size_t>(options_.min_correspondences)) continue;
    size_t key = visible;
    if (options_.sequential_order) {
      // Nearest in sequence to the last registered image first.
      const size_t distance =
          image_id > last_registered ? image_id - last_registered : last_registered - image_id;
      key = std::numeric_limits<size_t>::max() - distance;
    }
    scored.push_back({key, image_id});
  }
  std::sort(scored.begin(), scored.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first > b.first : a.second < b.second;
  });
  std::vector<image_t> ids;
  for (const auto& [score, id] : scored) ids.push_back(id);
  return ids;
}

void IncrementalMapper::SelectDegenerateFocal(const Reconstruction& empty,
                                              const InitialPairCandidate& pair,
                                              const PairGeometry& geometry, Reconstruction* rec,
                                              MapperSummary* summary) {
  // Two views in a critical configuration for self-calibration (optical axes through one point)
  // are consistent with any focal length: for the wrong one the pair's reconstruction is a
  // projective distortion of the scene (Sturm, "Critical motion sequences for the
  // self-calibration of cameras and stereo systems with variable focal length", 1999). A third
  // view, seen from elsewhere, tells: a camera with zero skew and unit aspect fits the
  // distorted structure only with larger reprojection errors. So each candidate scale of the
  // priors initialises the pair, registers the same next image, and is scored by that image's
  // truncated squared reprojection error over all its 2D-3D correspondences (MSAC's cost).
  // Scales a factor sqrt(2) apart from 1, widened towards the better side until the minimum is
  // bracketed (x0.5 .. x2 the prior, i.e. 0.6 .. 2.4 x the larger image side without EXIF), then
  // a parabola in log(scale) through the bracket.
  // entry-P10 (true f 920 px, prior 1229 px): grown from the prior, the model's focal lengths
  // drifted to 800-3200 px and its final adjustment took 51 + 50 iterations (5.4 s map); the
  // search picks 907 px, the final adjustment takes 16 iterations (2.4 s map).
  const std::vector<image_t> next = NextImageCandidates(*rec);
  if (next.empty()) return;
  const image_t probe = next.front();
  const double tau2 = options_.registration_max_error_px * options_.registration_max_error_px;
  // A trial skips the mapper's two-view adjustment (the calibration's own, with the focal
  // lengths held, has refined poses and points): fountain-P11-zoom's initialisation 0.65 -> 0.56 s,
  // and every trial is scored on the same footing.
  const auto evaluate = [&](double log_scale) {
    Reconstruction trial = empty;
    MapperSummary ignored;
    if (!Initialize(&trial, pair, geometry, /*accept_degenerate=*/true, &ignored,
                    std::exp(log_scale), /*adjust=*/false) ||
        !RegisterImage(&trial, probe))
      return std::numeric_limits<double>::infinity();
    const Image& image = trial.image(probe);
    const Camera& camera = trial.CameraOf(probe);
    const auto corrs = Correspondences(trial, probe);
    double sum = 0.0;
    for (const auto& c : corrs) {
      const double e =
          ReprojectionError(camera, image.cam_from_world, image.points2D[c.point2D_idx].xy,
                            trial.point3D(c.point3D_id).xyz);
      sum += std::min(tau2, e * e);
    }
    return corrs.empty() ? std::numeric_limits<double>::infinity() : sum / corrs.size();
  };
  const double step = 0.5 * std::log(2.0), limit = 2 * step;
  std::map<double, double> trials;  // score by log(scale)
  for (const double l : {-step, 0.0, step}) trials.emplace(l, evaluate(l));
  const auto best = [&trials] {
    return std::min_element(trials.begin(), trials.end(),
                            [](const auto& a, const auto& b) { return a.second < b.second; });
  };
  // Widen towards the better end while the best candidate is at an end.
  for (auto it = best(); it->first != 0.0; it = best()) {
    const double outward = it->first + (it->first > 0 ? step : -step);
    if (it != trials.begin() && std::next(it) != trials.end()) break;  // bracketed
    if (std::abs(outward) > limit + 1e-9) break;
    trials.emplace(outward, evaluate(outward));
  }
  auto it = best();
  if (it != trials.begin() && std::next(it) != trials.end() &&
      std::isfinite(std::prev(it)->second) && std::isfinite(std::next(it)->second)) {
    // Vertex of the parabola through the bracket (equally spaced).
    const double a = std::prev(it)->second, b = it->second, c = std::next(it)->second;
    const double curvature = a - 2 * b + c;
    if (curvature > 0) {
      const double vertex = it->first + 0.5 * step * (a - c) / curvature;
      trials.emplace(vertex, evaluate(vertex));
      it = best();
    }
  }
  std::string profile;
  for (const auto& [l, score] : trials)
    profile += fmt::format(" x{:.3f}: {:.3f}", std::exp(l), score);
  debug(
      "degenerate initial pair: focal x{:.3f} of the prior (truncated squared error of image "
      "{}, px^2:{})",
      std::exp(it->first), probe, profile);
  if (!std::isfinite(it->second) || it->first == 0.0) return;  // keep the prior's
  Reconstruction chosen = empty;
  MapperSummary chosen_summary = *summary;
  if (Initialize(&chosen, pair, geometry, /*accept_degenerate=*/true, &chosen_summary,
                 std::exp(it->first))) {
    *rec = std::move(chosen);
    *summary = chosen_summary;
  }
  registration_order_ = {pair.image_id1, pair.image_id2};
}

std::vector<IncrementalMapper::Correspondence2D3D> IncrementalMapper::Correspondences(
    const Reconstruction& rec, image_t image_id) const {
  // 2D-3D correspondences through tracks (Algorithm 2, over every registered image).
  const Image& image = rec.image(image_id);
  std::vector<Correspondence2D3D> corrs;
  for (point2D_t idx = 0; idx < image.points2D.size(); ++idx) {
    for (const auto& corr : graph_.CorrespondencesOf(image_id, idx)) {
      const Image& other = rec.image(corr.image_id);
      if (!other.registered) continue;
      const point3D_t pid = other.points2D[corr.point2D_idx].point3D_id;
      if (pid == kInvalidPoint3DId) continue;
      corrs.push_back({idx, pid});
      break;
    }
  }
  return corrs;
}

bool IncrementalMapper::RegisterImage(Reconstruction* rec, image_t image_id) {
  Image& image = rec->image(image_id);
  const std::vector<Correspondence2D3D> corrs = Correspondences(*rec, image_id);
  if (corrs.size() < static_cast<size_t>(std::max(options_.min_correspondences, 6))) return false;
  std::vector<Eigen::Vector2d> x;
  std::vector<Eigen::Vector3d> X;
  for (const auto& c : corrs) {
    x.push_back(image.points2D[c.point2D_idx].xy);
    X.push_back(rec->point3D(c.point3D_id).xyz);
  }

  Camera& camera = rec->CameraOf(image_id);
  const bool shared_camera = [&] {
    for (const image_t other : registration_order_)
      if (rec->image(other).camera_id == image.camera_id) return true;
    return false;
  }();
  // The focal length of the registered image this one shares most points with: the
  // starting value when the DLT's K is implausible (zoom changes slowly along a capture).
  std::map<image_t, size_t> shared_points;
  for (const auto& c : corrs)
    for (const auto& el : rec->point3D(c.point3D_id).track) ++shared_points[el.image_id];
  image_t neighbour = registration_order_.back();
  size_t best = 0;
  for (const auto& [id, count] : shared_points)
    if (count > best) best = count, neighbour = id;
  const Camera neighbour_camera = rec->CameraOf(neighbour);

  AbsolutePoseRefinementOptions refine;
  refine.intrinsics = MapperIntrinsics(options_, /*whole_model=*/false);
  if (shared_camera)
    refine.intrinsics = IntrinsicsOptions{false, false, false, false, false, false, {}};
  refine.intrinsics.refine_k1 = refine.intrinsics.refine_k2 = false;  // few points: BA does it

  struct Hypothesis {
    Camera camera;
    Rigid3d pose;
    size_t inliers = 0;
  };
  std::vector<Hypothesis> hypotheses;
  const auto refine_and_score = [&](Hypothesis h) {
    std::vector<Eigen::Vector2d> xi;
    std::vector<Eigen::Vector3d> Xi;
    for (size_t i = 0; i < x.size(); ++i)
      if (ReprojectionError(h.camera, h.pose, x[i], X[i]) <=
          4 * options_.registration_max_error_px) {
        xi.push_back(x[i]);
        Xi.push_back(X[i]);
      }
    if (xi.size() < 6 || !RefineAbsolutePose(refine, xi, Xi, &h.camera, &h.pose)) return;
    h.inliers = CountInliers(h.camera, h.pose, x, X, options_.registration_max_error_px);
    hypotheses.push_back(h);
  };

  // (a) The paper: RANSAC + DLT projection matrix, decomposed into K, R, t (section 4.3).
  RansacOptions ransac;
  ransac.max_error = options_.registration_max_error_px;
  ransac.seed = DeriveSeed(options_.seed, image_id);
  const auto p_report = EstimateProjectionMatrix(x, X, ransac);
  if (p_report.success) {
    Eigen::Matrix3d K, R;
    Eigen::Vector3d t;
    if (DecomposeProjectionMatrix(p_report.model, &K, &R, &t)) {
      Hypothesis h{shared_camera ? camera : neighbour_camera, Rigid3d(R, t), 0};
      if (!shared_camera && PlausibleCalibration(K, camera)) {
        // Keep the held parameters at their initial values (policy), take the rest from K.
        Camera from_dlt = camera;
        from_dlt.params[Camera::kK1] = neighbour_camera.params[Camera::kK1];
        from_dlt.params[Camera::kK2] = neighbour_camera.params[Camera::kK2];
        from_dlt.focal() = 0.5 * (K(0, 0) + K(1, 1));
        if (options_.refine_aspect) from_dlt.params[Camera::kAspect] = K(1, 1) / K(0, 0);
        if (options_.refine_skew) from_dlt.params[Camera::kSkew] = K(0, 1);
        // Parameters shared per image size start from the group's current values.
        if (neighbour_camera.width == camera.width && neighbour_camera.height == camera.height)
          for (const int i : MapperIntrinsics(options_, true).shared_per_size)
            from_dlt.params[i] = neighbour_camera.params[i];
        if (options_.refine_principal_point) {
          from_dlt.params[Camera::kU0] = K(0, 2);
          from_dlt.params[Camera::kV0] = K(1, 2);
        }
        h.camera = from_dlt;
      }
      refine_and_score(h);
    }
  }
  // (b) Fallback: PnP with the neighbour's intrinsics (robust on nearly planar point sets,
  // where the DLT is ill-posed), then the same refinement frees the focal length.
  {
    const Camera start = shared_camera ? camera : neighbour_camera;
    std::vector<cv::Point2d> image_points;
    std::vector<cv::Point3d> object_points;
    for (size_t i = 0; i < x.size(); ++i) {
      const Eigen::Vector2d n = start.ImageToNormalized(x[i]);
      image_points.emplace_back(n.x(), n.y());
      object_points.emplace_back(X[i].x(), X[i].y(), X[i].z());
    }
    cv::Mat rvec, tvec;
    cv::setRNGSeed(static_cast<int>(DeriveSeed(options_.seed, image_id) & 0x7fffffff));
    if (cv::solvePnPRansac(object_points, image_points, cv::Mat::eye(3, 3, CV_64F), cv::noArray(),
                           rvec, tvec, false, 1000,
                           options_.registration_max_error_px / start.focal(), 0.9999,
                           cv::noArray(), cv::SOLVEPNP_AP3P)) {
      cv::Mat Rcv;
      cv::Rodrigues(rvec, Rcv);
      Eigen::Matrix3d R;
      Eigen::Vector3d t;
      cv::cv2eigen(Rcv, R);
      cv::cv2eigen(tvec, t);
      refine_and_score({start, Rigid3d(R, t), 0});
    }
  }
  if (hypotheses.empty()) return false;
  const Hypothesis& chosen = *std::max_element(
      hypotheses.begin(), hypotheses.end(),
      [](const Hypothesis& a, const Hypothesis& b) { return a.inliers < b.inliers; });
  if (chosen.inliers < static_cast<size_t>(options_.min_registration_inliers)) return false;
  const double size = std::max(camera.width, camera.height);
  if (chosen.camera.focal() < 0.2 * size || chosen.camera.focal() > 10 * size) return false;

  if (!shared_camera) camera.params = chosen.camera.params;
  image.cam_from_world = chosen.pose;
  rec->RegisterImage(image_id);
  ExtendFrontier(image_id);
  for (size_t i = 0; i < corrs.size(); ++i)
    if (ReprojectionError(camera, image.cam_from_world, x[i], X[i]) <=
        options_.registration_max_error_px)
      rec->AddObservation(corrs[i].point3D_id, {image_id, corrs[i].point2D_idx});
  debug("registered image {} ({}) with {} inliers of {}, f {:.1f}", image_id, image.name,
        chosen.inliers, corrs.size(), camera.focal());
  return true;
}

size_t IncrementalMapper::TriangulateImage(Reconstruction* rec, image_t image_id) {
  const double max_error = options_.triangulation_max_error_px;
  const double min_angle = options_.min_triangulation_angle_deg * kDegree;
  size_t added = 0;
  const size_t num_points2D = rec->image(image_id).points2D.size();
  for (point2D_t idx = 0; idx < num_points2D; ++idx) {
    if (rec->image(image_id).points2D[idx].HasPoint3D()) continue;
    const auto& corrs = graph_.CorrespondencesOf(image_id, idx);
    if (corrs.empty()) continue;

    // Continue an existing track when the point reprojects well here.
    point3D_t best_id = kInvalidPoint3DId;
    double best_error = max_error;
    std::vector<TrackElement> fresh = {{image_id, idx}};
    for (const auto& corr : corrs) {
      const Image& other = rec->image(corr.image_id);
      if (!other.registered) continue;
      const point3D_t pid = other.points2D[corr.point2D_idx].point3D_id;
      if (pid == kInvalidPoint3DId) {
        fresh.push_back({corr.image_id, corr.point2D_idx});
        continue;
      }
      const double error =
          std::sqrt(rec->SquaredReprojectionError({image_id, idx}, rec->point3D(pid).xyz));
      if (error < best_error) best_error = error, best_id = pid;
    }
    if (best_id != kInvalidPoint3DId) {
      rec->AddObservation(best_id, {image_id, idx});
      continue;
    }
    if (fresh.size() < 2) continue;

    // A new point from every registered view that sees it: linear multi-view triangulation in
    // normalised coordinates, then refinement of the pixel error through each camera.
    std::vector<Matrix34d> Ps;
    std::vector<Eigen::Vector2d> normalized, pixels;
    std::vector<Camera> cameras;
    std::vector<Rigid3d> poses;
    for (const auto& el : fresh) {
      const Image& im = rec->image(el.image_id);
      Ps.push_back(im.cam_from_world.ToMatrix());
      cameras.push_back(rec->camera(im.camera_id));
      poses.push_back(im.cam_from_world);
      pixels.push_back(im.points2D[el.point2D_idx].xy);
      normalized.push_back(cameras.back().ImageToNormalized(pixels.back()));
    }
    Eigen::Vector3d X;
    if (!TriangulateMultiView(Ps, normalized, &X)) continue;
    RefineTriangulatedPoint(cameras, poses, pixels, &X);
    std::vector<TrackElement> track;
    std::vector<Eigen::Vector3d> centers;
    for (size_t k = 0; k < fresh.size(); ++k) {
      if (!HasPositiveDepth(poses[k], X)) continue;
      if (ReprojectionError(cameras[k], poses[k], pixels[k], X) > max_error) continue;
      track.push_back(fresh[k]);
      centers.push_back(poses[k].Center());
    }
    if (track.size() < 2 || track.front().image_id != image_id) continue;
    double angle = 0;
    for (size_t a = 0; a < centers.size() && angle < min_angle; ++a)
      for (size_t b = a + 1; b < centers.size() && angle < min_angle; ++b)
        angle = std::max(angle, TriangulationAngle(centers[a], centers[b], X));
    if (angle < min_angle) continue;
    rec->AddPoint3D(X, track);
    ++added;
  }
  return added;
}

void IncrementalMapper::LocalBundleAdjustment(Reconstruction* rec, MapperSummary* summary) {
  Timer timer;
  const size_t m0 = std::min<size_t>(options_.local_ba_images, registration_order_.size());
  const std::vector<image_t> window(registration_order_.end() - m0, registration_order_.end());
  BundleAdjustmentOptions ba;
  ba.intrinsics = MapperIntrinsics(options_, /*whole_model=*/false);
  ba.num_threads = options_.num_threads;
  ba.solver = options_.ba_solver;
  ba.max_iterations = 25;  // as COLMAP's local BA: the global ones finish the job
  ba.function_tolerance = options_.local_ba_function_tolerance;
  ba.verbose = spdlog::should_log(spdlog::level::trace);
  const auto ba_summary = RunBundleAdjustment(
      ba, BundleAdjustmentConfig::Local(*rec, window, options_.local_ba_max_track_length), rec);
  debug("local BA: {} residuals, {} iterations, {:.3f} s, RMS {:.3f} -> {:.3f} px",
        ba_summary.num_residuals, ba_summary.iterations, ba_summary.seconds,
        ba_summary.initial_rms_px, ba_summary.final_rms_px);
  rec->FilterObservationsWithLargeError(options_.filter_max_error_px, window);
  rec->FilterPointsWithSmallTriangulationAngle(options_.min_triangulation_angle_deg, window);
  ++summary->num_local_ba;
  summary->seconds_local_ba += timer.Seconds();
}

void IncrementalMapper::GlobalBundleAdjustment(Reconstruction* rec, MapperSummary* summary,
                                               bool retriangulate, int max_iterations,
                                               double function_tolerance) {
  Timer timer;
  BundleAdjustmentOptions ba;
  ba.intrinsics = MapperIntrinsics(options_, /*whole_model=*/true);
  ba.num_threads = options_.num_threads;
  ba.solver = options_.ba_solver;
  ba.max_iterations = max_iterations;
  ba.function_tolerance = function_tolerance;
  ba.trust_region = options_.global_ba_trust_region;
  // `--log-level trace`: Ceres' iterations and full report (where the solver's time goes).
  ba.verbose = spdlog::should_log(spdlog::level::trace);
  const auto ba_summary = RunBundleAdjustment(ba, BundleAdjustmentConfig::Global(*rec), rec);
  debug("global BA: {} residuals, {} iterations, {:.3f} s, RMS {:.3f} -> {:.3f} px",
        ba_summary.num_residuals, ba_summary.iterations, ba_summary.seconds,
        ba_summary.initial_rms_px, ba_summary.final_rms_px);
  if (spdlog::should_log(spdlog::level::debug)) {
    std::string focals;
    for (const image_t id : registration_order_)
      focals += fmt::format(" {}:{:.0f}", id, rec->CameraOf(id).focal());
    debug("focal lengths after the global BA:{}", focals);
  }
  rec->FilterObservationsWithLargeError(options_.filter_max_error_px);
  rec->FilterPointsWithSmallTriangulationAngle(options_.min_triangulation_angle_deg);
  if (retriangulate) {
    // Re-triangulation: with better poses and intrinsics, more tracks pass the checks.
    size_t added = 0;
    for (const image_t id : registration_order_) added += TriangulateImage(rec, id);
    debug("re-triangulation: {} observations added to {} points", added, rec->points3D().size());
    // Another adjustment only when re-triangulation changed the model noticeably: on
    // fountain-P11 the final one adds 16 observations to 60,000 and a second adjustment cost
    // 1.1 s (a sixth of the mapper) for no measurable change.
    if (added > 0.01 * rec->NumObservations()) {
      summary->num_global_ba_iterations +=
          RunBundleAdjustment(ba, BundleAdjustmentConfig::Global(*rec), rec).iterations;
      rec->FilterObservationsWithLargeError(options_.filter_max_error_px);
      rec->FilterPointsWithSmallTriangulationAngle(options_.min_triangulation_angle_deg);
    }
  }
  summary->num_global_ba_iterations += ba_summary.iterations;
  ++summary->num_global_ba;
  summary->seconds_global_ba += timer.Seconds();
}

}  // namespace varsfm
