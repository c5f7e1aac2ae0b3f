#pragma once
// When the incremental mapper adjusts what (El Hazzat et al., Algorithm 1): a local bundle
// adjustment over the last m0 images after each registration, a global one when M0 images are
// registered and one at the end. Beyond the paper: further global adjustments each time the
// model has grown by a factor, and one early global adjustment after a degenerate initial pair.
// The options also say how each adjustment runs (iterations, tolerances, trust region) and
// which observations are filtered after it.
#include <cstddef>

#include "varsfm/ba/bundle_adjuster.h"

namespace varsfm {

struct BundleAdjustmentScheduleOptions {
  int local_ba_images = 3;  // m0 of the paper
  // Beyond the paper: in a local adjustment, points seen by more images than this are held and
  // enter only through the window's observations (0: every point free with its whole track). As
  // COLMAP (15); it keeps the local adjustments' cost bounded on long sequences (bench/scale).
  int local_ba_max_track_length = 15;
  // Local adjustments only keep the new images consistent, the global ones reach the minimum:
  // they stop at 25 iterations (as COLMAP's) or at this relative cost decrease (Ceres' function
  // tolerance).
  int local_ba_max_iterations = 25;
  double local_ba_function_tolerance = 1e-3;

  int first_global_ba_images = 13;  // M0 of the paper (10..20); 0: after every image
  // Beyond the paper: a further global BA each time the model has grown by this factor since
  // the last one (0 disables: the paper's schedule).
  double global_ba_growth = 1.4;
  // M0's and the final adjustment's tolerance. At 1e-5 the final adjustment of a 1000-photo set
  // took 11 steps where 1e-4 takes 6, for the same figures on every shared set and 0.0001 m more
  // mean centre error there (docs/measurements.md, "The final adjustment's tolerance").
  double global_ba_function_tolerance = 1e-4;
  // The growth adjustments' tolerance: each is followed by others and by the final one
  // (docs/mapper.md has the measurements on bench/scale).
  double growth_ba_function_tolerance = 1e-4;
  // The global adjustments' trust region. The dogleg by default: on long sequences it ends
  // nearer the minimum in fewer factorisations than Levenberg-Marquardt, whose damping holds
  // back the weak directions (per-image distortion against pose, a street's bend); a rejected
  // dogleg step reuses its factorisation. The local adjustments (3 steps) stay on LM.
  BundleAdjustmentOptions::TrustRegion global_ba_trust_region =
      BundleAdjustmentOptions::TrustRegion::kDogleg;
  // Beyond the paper: in the global adjustments while the model grows (not the final one, nor
  // M0's), once at least growth_ba_subset_min_images images are registered, a point enters with
  // at most this many of its observations, spread over its track (0: all;
  // BundleAdjustmentConfig::max_point_observations). On a set whose images densify, a point's
  // track grows with the images and the exact adjustment with the sum of the squared track
  // lengths. The final adjustment stays complete and settles what the subsets leave (measured
  // in docs/measurements.md, "Track subsets in the growth adjustments"). Sets of fewer than
  // growth_ba_subset_min_images images are untouched.
  int growth_ba_max_point_observations = 10;
  int growth_ba_subset_min_images = 200;
  // Beyond the paper: a global adjustment of at least this many images solves its reduced
  // camera system by preconditioned conjugate gradients (0: never; ba/reduced_camera_pcg.cc):
  // on a set that densifies the sparse factorisation's fill approaches a dense one (n^3). Off
  // by default: with the block-Jacobi preconditioner it converges slowly enough to cost what the
  // factorisation costs (bench/results/2026-12-03-global-ba-cg.md; 250 is the measured setting).
  int global_ba_iterative_min_images = 0;
  // Their conjugate gradients stop at this relative residual or iteration count.
  double global_ba_cg_tolerance = 1e-3;
  int global_ba_cg_max_iterations = 200;
  // Iteration cap of the global adjustments while the model grows: on long sequences some crawl
  // along weak directions at ~1e-4 relative decrease per iteration, and others follow.
  int global_ba_max_iterations = 25;
  // After a degenerate initial pair (focal lengths held in its two-view adjustment), a global
  // adjustment when this many images are registered (0: none): once the images determine the
  // focal lengths it settles them before the model grows on them.
  int degenerate_init_global_ba_images = 4;
  // The paper's global adjustment at the end; off (with no M0 / growth adjustments) gives the
  // local-only, Mouragnon-like baseline of the benchmarks.
  bool final_global_ba = true;
  int final_global_ba_max_iterations = 50;
  // After the final adjustment, the points seen by two images only with an observation above
  // this factor x the model's RMS reprojection error are removed, and the model is adjusted once
  // more (to growth_ba_function_tolerance: it starts at the optimum); 0: not. No third view can
  // expose a wrong match that fits a wrong epipolar geometry within the verification threshold,
  // and on a nearly planar scene a few dozen of them pull every focal length along the
  // focal-length / depth valley (bench/results/2026-12-04-s14-two-view-filter.md).
  double final_two_view_filter_factor = 2.0;

  // After each adjustment, observations with a larger reprojection error (px) are removed, and
  // points whose views are less than this far apart (deg): the triangulation's thresholds
  // (track_triangulation.h), so what it accepts survives the filter.
  double filter_max_error_px = 4.0;
  double filter_min_triangulation_angle_deg = 1.5;
  // After a global adjustment the model is re-triangulated; another adjustment follows only when
  // that added more new points than this fraction of the observations (a handful on a settled
  // model changes nothing measurable, and the adjustment would cost as much as the first).
  double readjust_min_new_points_fraction = 0.01;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value

  // The growth adjustment's cap on observations per point with `num_registered` images (0: none).
  size_t GrowthPointObservations(size_t num_registered) const {
    return num_registered >= static_cast<size_t>(growth_ba_subset_min_images)
               ? static_cast<size_t>(growth_ba_max_point_observations)
               : 0;
  }
};

// What follows a registration.
enum class ScheduledAdjustment {
  kLocal,
  kGlobal,        // M0 reached (or M0 = 0: after every image)
  kGrowth,        // the model grew by global_ba_growth since the last global adjustment
  kSettleFocals,  // a degenerate initial pair's focal lengths, once the images determine them
};

class BundleAdjustmentSchedule {
 public:
  explicit BundleAdjustmentSchedule(const BundleAdjustmentScheduleOptions& options)
      : options_(options) {}

  // The adjustment after the registration that made `num_registered` of `num_images` images;
  // `degenerate_init`: the initial pair's self-calibration was degenerate.
  ScheduledAdjustment Next(size_t num_registered, size_t num_images, bool degenerate_init);

 private:
  const BundleAdjustmentScheduleOptions& options_;
  size_t last_global_size_ = 2;  // the initial pair's two-view adjustment
  bool first_global_done_ = false;
};

}  // namespace varsfm
