#include "varsfm/sfm/incremental_mapper.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <set>

#include "varsfm/ba/bundle_adjuster.h"
#include "varsfm/calibration/two_view_calibration.h"
#include "varsfm/estimators/two_view_estimators.h"
#include "varsfm/geometry/fundamental.h"
#include "varsfm/geometry/triangulation.h"
#include "varsfm/util/log.h"
#include "varsfm/util/timer.h"

namespace varsfm {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;
// How often a run's progress line shows a fresh RMS (it costs a pass over the model).
constexpr size_t kProgressUpdates = 20;

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

  // 1. Initialisation.
  Timer timer;
  if (!InitializeModel(rec, &summary)) return summary;
  summary.seconds_initialization = timer.Seconds();
  if (options_.progress) options_.progress(2, summary.num_images, rec->RmsReprojectionError());

  // 2. The other images one by one.
  RegisterAll(rec, &summary);

  // 3. Final global adjustment (with re-triangulation and filtering).
  const BundleAdjustmentScheduleOptions& schedule = options_.adjustment;
  if (schedule.final_global_ba) {
    GlobalBundleAdjustment(rec, &summary, /*retriangulate=*/true,
                           schedule.final_global_ba_max_iterations,
                           schedule.global_ba_function_tolerance);
    if (schedule.final_two_view_filter_factor > 0) {
      const double max_error = schedule.final_two_view_filter_factor * rec->RmsReprojectionError();
      const size_t removed = rec->FilterTwoViewPointsWithLargeError(max_error);
      summary.num_two_view_points_removed = removed;
      debug("{} two-view points above {:.3f} px removed", removed, max_error);
      if (removed > 0)
        GlobalBundleAdjustment(rec, &summary, /*retriangulate=*/false,
                               schedule.final_global_ba_max_iterations,
                               schedule.growth_ba_function_tolerance);
    }
  }
  rec->UpdatePointErrors();
  summary.num_registered = rec->NumRegisteredImages();
  summary.success = true;
  return summary;
}

bool IncrementalMapper::InitializeModel(Reconstruction* rec, MapperSummary* summary) {
  // Candidates by the disparity criterion; the first pair whose self-calibration is not
  // degenerate wins, else the best degenerate one (prior focal; InitialPairAttempts).
  const auto candidates =
      RankInitialPairs(*rec, graph_, excluded_initial_pairs_, options_.initial_pair);
  if (candidates.empty()) {
    summary->message = NoInitialPairReason(graph_, excluded_initial_pairs_, options_.initial_pair);
    return false;
  }
  // Cheap first pass: F and the conditioning of the closed-form focal lengths for the best
  // candidates; then full calibration of well-conditioned pairs first, in score order.
  const Reconstruction empty = *rec;
  const int trials = std::min<int>(options_.max_initial_pair_trials, candidates.size());
  std::vector<PairGeometry> geometries;
  for (int k = 0; k < trials; ++k) geometries.push_back(EstimatePairGeometry(*rec, candidates[k]));
  std::vector<bool> usable, well_conditioned;
  for (const PairGeometry& geometry : geometries) {
    usable.push_back(geometry.success);
    well_conditioned.push_back(geometry.well_conditioned);
  }
  bool initialized = false;
  int initial = -1;
  for (const InitialPairAttempt& attempt : InitialPairAttempts(usable, well_conditioned)) {
    const int k = attempt.candidate;
    *rec = empty;
    initialized = Initialize(rec, candidates[k], geometries[k], attempt.accept_degenerate, summary);
    initial = k;
    if (initialized) break;
  }
  if (initialized && summary->initial_focal_from_prior && options_.degenerate_init_focal_search)
    SelectDegenerateFocal(empty, candidates[initial], geometries[initial], rec, summary);
  if (!initialized) {
    *rec = empty;
    summary->message =
        "no image pair could be initialised (too little parallax, or matches explained "
        "by a rotation or a plane)";
  }
  return initialized;
}

void IncrementalMapper::RegisterAll(Reconstruction* rec, MapperSummary* summary) {
  const BundleAdjustmentScheduleOptions& schedule_options = options_.adjustment;
  BundleAdjustmentSchedule schedule(schedule_options);
  double progress_rms = -1.0;
  VisiblePointCounts counts(graph_);
  const ObservedReconstruction observed(rec, &counts);
  const ImageRegistrationOptions relaxed_options = options_.registration.Relaxed();
  bool relaxed = false;  // this pass over the candidates is at the relaxed thresholds
  while (true) {
    bool registered_any = false;
    for (const image_t image_id : NextImageCandidates(*rec, counts)) {
      Timer reg_timer;
      const bool ok =
          RegisterImage(rec, image_id, relaxed ? relaxed_options : options_.registration);
      summary->seconds_registration += reg_timer.Seconds();
      if (!ok) continue;
      if (relaxed) {
        ++summary->num_relaxed_registrations;
        debug("image {} registered at the relaxed thresholds", image_id);
      }
      registration_order_.push_back(image_id);
      Timer tri_timer;
      TriangulateImage(graph_, options_.triangulation, image_id, rec);
      summary->seconds_triangulation += tri_timer.Seconds();

      const size_t n = rec->NumRegisteredImages();
      switch (schedule.Next(n, summary->num_images, summary->initial_calibration_degenerate)) {
        case ScheduledAdjustment::kGlobal:
        case ScheduledAdjustment::kSettleFocals:
          GlobalBundleAdjustment(rec, summary, /*retriangulate=*/true,
                                 schedule_options.global_ba_max_iterations,
                                 schedule_options.global_ba_function_tolerance);
          break;
        case ScheduledAdjustment::kGrowth:
          GlobalBundleAdjustment(rec, summary, /*retriangulate=*/true,
                                 schedule_options.global_ba_max_iterations,
                                 schedule_options.growth_ba_function_tolerance,
                                 schedule_options.GrowthPointObservations(n));
          break;
        case ScheduledAdjustment::kLocal:
          LocalBundleAdjustment(rec, summary);
          break;
      }
      if (options_.progress) {
        // The model's RMS costs a pass over every observation: refreshed kProgressUpdates times
        // a run, so that reporting stays linear in the number of images.
        const size_t every = std::max<size_t>(1, summary->num_images / kProgressUpdates);
        if (n % every == 0 || n == summary->num_images || progress_rms < 0)
          progress_rms = rec->RmsReprojectionError();
        options_.progress(n, summary->num_images, progress_rms);
      }
      registered_any = true;
      break;  // candidates change with every registration
    }
    if (registered_any) {
      relaxed = false;
      continue;
    }
    if (relaxed || options_.registration.relaxed_min_inliers == 0) break;
    relaxed = true;
  }
}

IncrementalMapper::PairGeometry IncrementalMapper::EstimatePairGeometry(
    const Reconstruction& rec, const InitialPairCandidate& pair) const {
  PairGeometry geometry;
  const FeatureMatches matches = graph_.MatchesBetween(pair.image_id1, pair.image_id2);
  if (const auto verified = graph_.FundamentalMatrix(pair.image_id1, pair.image_id2)) {
    // Geometric verification's F; its inliers (the pair's matches) within the initial pair's
    // threshold, all of them when matching used the same one.
    geometry.F = *verified;
    const double max_error2 = options_.init_max_error_px * options_.init_max_error_px;
    for (const auto& m : matches)
      if (SampsonErrorSquared(geometry.F, rec.image(pair.image_id1).points2D[m.point2D_idx1].xy,
                              rec.image(pair.image_id2).points2D[m.point2D_idx2].xy) < max_error2)
        geometry.inlier_matches.push_back(m);
  } else {
    // A graph without F (not from a workspace's verification): F by LO-RANSAC here.
    std::vector<Eigen::Vector2d> x1, x2;
    for (const auto& m : matches) {
      x1.push_back(rec.image(pair.image_id1).points2D[m.point2D_idx1].xy);
      x2.push_back(rec.image(pair.image_id2).points2D[m.point2D_idx2].xy);
    }
    RansacOptions ransac;
    ransac.max_error = options_.init_max_error_px;
    ransac.seed = DeriveSeed(options_.seed, pair.image_id1 * 65536ull + pair.image_id2);
    const auto report = EstimateFundamentalMatrix(x1, x2, ransac);
    if (!report.success) return geometry;
    geometry.F = report.model;
    for (size_t i = 0; i < matches.size(); ++i)
      if (report.inlier_mask[i]) geometry.inlier_matches.push_back(matches[i]);
  }
  geometry.success = true;
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
    ba.intrinsics = options_.intrinsics.ForAdjustment(/*whole_model=*/true);
    if (calib.degenerate) ba.intrinsics.refine_focal = false;
    ba.num_threads = options_.num_threads;
    ba.solver = options_.ba_solver;
    RunBundleAdjustment(ba, BundleAdjustmentConfig::Global(*rec), rec);
    rec->FilterObservationsWithLargeError(options_.adjustment.filter_max_error_px);
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

std::vector<image_t> IncrementalMapper::NextImageCandidates(
    const Reconstruction& rec, const VisiblePointCounts& counts) const {
  // Score: the number of the image's 2D points whose tracks reach a reconstructed 3D point, kept
  // by `counts` as the model changes. An image that matches no registered one scores 0.
  std::vector<std::pair<size_t, image_t>> scored;
  image_t last_registered = registration_order_.empty() ? 0 : registration_order_.back();
  for (const image_t image_id : frontier_) {
    if (!rec.ExistsImage(image_id)) continue;  // frontier_ holds graph images only
    if (rec.image(image_id).registered) continue;
    const size_t visible = counts.VisiblePoints(image_id);
    if (visible < static_cast<size_t>(options_.registration.min_correspondences)) continue;
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

double IncrementalMapper::TruncatedRegistrationError(const Reconstruction& rec,
                                                     image_t probe) const {
  const double tau2 = options_.registration.max_error_px * options_.registration.max_error_px;
  const Image& image = rec.image(probe);
  const Camera& camera = rec.CameraOf(probe);
  const auto corrs = FindCorrespondences2D3D(graph_, rec, probe);
  double sum = 0.0;
  for (const auto& c : corrs) {
    const double e =
        ReprojectionError(camera, image.cam_from_world, image.points2D[c.point2D_idx].xy,
                          rec.point3D(c.point3D_id).xyz);
    sum += std::min(tau2, e * e);
  }
  return corrs.empty() ? std::numeric_limits<double>::infinity() : sum / corrs.size();
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
  // a parabola in log(scale) through the bracket. On entry-P10 (true f 920 px, prior 1229 px)
  // the search picks 907 px, where a model grown from the prior lets its focal lengths drift
  // (docs/measurements.md).
  VisiblePointCounts counts(graph_);
  counts.Recount(*rec);
  const std::vector<image_t> next = NextImageCandidates(*rec, counts);
  if (next.empty()) return;
  const image_t probe = next.front();
  // A trial skips the mapper's two-view adjustment (the calibration's own, with the focal
  // lengths held, has refined poses and points): it saves time, and every trial is scored on
  // the same footing.
  const auto evaluate = [&](double log_scale) {
    Reconstruction trial = empty;
    MapperSummary ignored;
    if (!Initialize(&trial, pair, geometry, /*accept_degenerate=*/true, &ignored,
                    std::exp(log_scale), /*adjust=*/false) ||
        !RegisterImage(&trial, probe, options_.registration))
      return std::numeric_limits<double>::infinity();
    return TruncatedRegistrationError(trial, probe);
  };
  const double step = options_.degenerate_focal_log_step;
  const double limit = options_.degenerate_focal_max_steps * step;
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

bool IncrementalMapper::RegisterImage(Reconstruction* rec, image_t image_id,
                                      const ImageRegistrationOptions& options) {
  if (!varsfm::RegisterImage(graph_, options, options_.intrinsics, registration_order_,
                             options_.seed, image_id, rec))
    return false;
  ExtendFrontier(image_id);
  return true;
}

void IncrementalMapper::LocalBundleAdjustment(Reconstruction* rec, MapperSummary* summary) {
  Timer timer;
  const BundleAdjustmentScheduleOptions& schedule = options_.adjustment;
  const size_t m0 = std::min<size_t>(schedule.local_ba_images, registration_order_.size());
  const std::vector<image_t> window(registration_order_.end() - m0, registration_order_.end());
  BundleAdjustmentOptions ba;
  ba.intrinsics = options_.intrinsics.ForAdjustment(/*whole_model=*/false);
  ba.num_threads = options_.num_threads;
  ba.solver = options_.ba_solver;
  ba.max_iterations = schedule.local_ba_max_iterations;
  ba.function_tolerance = schedule.local_ba_function_tolerance;
  ba.verbose = spdlog::should_log(spdlog::level::trace);
  const auto ba_summary = RunBundleAdjustment(
      ba, BundleAdjustmentConfig::Local(*rec, window, schedule.local_ba_max_track_length), rec);
  debug("local BA: {} residuals, {} iterations, {:.3f} s, RMS {:.3f} -> {:.3f} px",
        ba_summary.num_residuals, ba_summary.iterations, ba_summary.seconds,
        ba_summary.initial_rms_px, ba_summary.final_rms_px);
  rec->FilterObservationsWithLargeError(schedule.filter_max_error_px, window);
  rec->FilterPointsWithSmallTriangulationAngle(schedule.filter_min_triangulation_angle_deg, window);
  ++summary->num_local_ba;
  summary->seconds_local_ba += timer.Seconds();
}

void IncrementalMapper::GlobalBundleAdjustment(Reconstruction* rec, MapperSummary* summary,
                                               bool retriangulate, int max_iterations,
                                               double function_tolerance,
                                               size_t max_point_observations) {
  Timer timer;
  const BundleAdjustmentScheduleOptions& schedule = options_.adjustment;
  BundleAdjustmentOptions ba;
  ba.intrinsics = options_.intrinsics.ForAdjustment(/*whole_model=*/true);
  ba.num_threads = options_.num_threads;
  ba.solver = options_.ba_solver;
  ba.max_iterations = max_iterations;
  ba.function_tolerance = function_tolerance;
  ba.trust_region = schedule.global_ba_trust_region;
  ba.iterative_min_images = schedule.global_ba_iterative_min_images;
  ba.iterative_tolerance = schedule.global_ba_cg_tolerance;
  ba.iterative_max_iterations = schedule.global_ba_cg_max_iterations;
  // `--log-level trace`: Ceres' iterations and full report (where the solver's time goes).
  ba.verbose = spdlog::should_log(spdlog::level::trace);
  const auto global_config = [&] {
    BundleAdjustmentConfig config = BundleAdjustmentConfig::Global(*rec);
    config.max_point_observations = max_point_observations;
    return config;
  };
  const auto ba_summary = RunBundleAdjustment(ba, global_config(), rec);
  debug("global BA: {} residuals, {} iterations, {:.3f} s, RMS {:.3f} -> {:.3f} px",
        ba_summary.num_residuals, ba_summary.iterations, ba_summary.seconds,
        ba_summary.initial_rms_px, ba_summary.final_rms_px);
  if (spdlog::should_log(spdlog::level::debug)) {
    std::string focals;
    for (const image_t id : registration_order_)
      focals += fmt::format(" {}:{:.0f}", id, rec->CameraOf(id).focal());
    debug("focal lengths after the global BA:{}", focals);
  }
  rec->FilterObservationsWithLargeError(schedule.filter_max_error_px);
  rec->FilterPointsWithSmallTriangulationAngle(schedule.filter_min_triangulation_angle_deg);
  if (retriangulate) {
    // Re-triangulation: with better poses and intrinsics, more tracks pass the checks.
    size_t added = 0;
    for (const image_t id : registration_order_)
      added += TriangulateImage(graph_, options_.triangulation, id, rec);
    debug("re-triangulation: {} new points, {} in all", added, rec->points3D().size());
    // Another adjustment only when re-triangulation changed the model noticeably.
    if (added > schedule.readjust_min_new_points_fraction * rec->NumObservations()) {
      summary->num_global_ba_iterations += RunBundleAdjustment(ba, global_config(), rec).iterations;
      rec->FilterObservationsWithLargeError(schedule.filter_max_error_px);
      rec->FilterPointsWithSmallTriangulationAngle(schedule.filter_min_triangulation_angle_deg);
    }
  }
  summary->num_global_ba_iterations += ba_summary.iterations;
  ++summary->num_global_ba;
  summary->seconds_global_ba += timer.Seconds();
}

}  // namespace varsfm
