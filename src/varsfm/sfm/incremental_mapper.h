#pragma once
// The incremental mapper: Algorithm 1 of El Hazzat et al., on a camera whose intrinsics change
// from image to image.
//   1. initial pair by the disparity criterion (initial_pair.h), two-view self-calibration,
//      triangulation and two-view bundle adjustment with k1, k2;
//   2. for each next image: 2D-3D correspondences through the tracks of every registered image,
//      RANSAC + DLT projection matrix (>= n0 = 6 correspondences), decomposition into K, R, t,
//      non-linear refinement of the pose and free intrinsics on the inliers; triangulation of
//      new points with every registered image it matches; local bundle adjustment over the last
//      m0 images; a global bundle adjustment when M0 images are registered and at the end.
// Beyond the paper (as robust systems do): next-best-view order, retries of images that failed
// to register, outlier filtering after each bundle adjustment, re-triangulation, further global
// adjustments as the model grows, and a PnP fallback when the DLT's K is implausible (a nearly
// planar set of points makes the DLT ill-posed).
#include <cmath>
#include <cstdint>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include "varsfm/ba/bundle_adjuster.h"
#include "varsfm/scene/reconstruction.h"
#include "varsfm/sfm/bundle_adjustment_schedule.h"
#include "varsfm/sfm/correspondence_graph.h"
#include "varsfm/sfm/image_registration.h"
#include "varsfm/sfm/initial_pair.h"
#include "varsfm/sfm/intrinsics_policy.h"
#include "varsfm/sfm/track_triangulation.h"
#include "varsfm/sfm/visible_point_counts.h"
#include "varsfm/util/random.h"

namespace varsfm {

// The mapper's options, each part with its defaults in its own header: initial pair
// (initial_pair.h), registration (image_registration.h), triangulation (track_triangulation.h),
// bundle adjustments (bundle_adjustment_schedule.h), intrinsics (intrinsics_policy.h); here
// the initialisation's and the whole run's.
struct IncrementalMapperOptions {
  InitialPairOptions initial_pair;
  // Candidates by the disparity criterion that are calibrated and tried, best first.
  int max_initial_pair_trials = 10;
  int min_initial_points = 50;
  // The initial pair's points must have this median triangulation angle: a pure rotation or
  // a too-short baseline gives near-zero angles (and a meaningless structure).
  double init_min_median_angle_deg = 3.0;
  // The initial pair's matches are the inliers of its verified F within this Sampson distance
  // (px), should matching have used a looser threshold: the self-calibration reads the focal
  // lengths from F and the two-view BA starts from these matches. Also the threshold of the
  // LO-RANSAC for F of a graph that carries none.
  double init_max_error_px = 1.5;
  // A degenerate initial pair's focal length is chosen by a third view (SelectDegenerateFocal)
  // instead of taken from the prior: scales of the prior this far apart in log(scale) (sqrt(2)),
  // widened up to this many steps from 1 (x0.5 .. x2 the prior: 0.6 .. 2.4 x the larger image
  // side without EXIF), then a parabola through the bracket.
  bool degenerate_init_focal_search = true;
  double degenerate_focal_log_step = 0.5 * std::log(2.0);
  int degenerate_focal_max_steps = 2;

  ImageRegistrationOptions registration;
  TrackTriangulationOptions triangulation;
  BundleAdjustmentScheduleOptions adjustment;
  IntrinsicsPolicy intrinsics;

  // Next image: the one that sees the most reconstructed points (next-best view), or the
  // next in sequence order for ordered input (video, numbered photos).
  bool sequential_order = false;

  // The bundle adjustments' linear solver (kAuto: chosen by the number of images).
  BundleAdjustmentOptions::Solver ba_solver = BundleAdjustmentOptions::Solver::kAuto;
  // Bundle adjustment threads (0: all cores for the native solver, whose result is the same bit
  // for bit with any number; see ba/bundle_adjuster.h).
  int num_threads = 0;
  uint64_t seed = kDefaultSeed;
  // Called after each registration: (registered, total, RMS reprojection error px).
  std::function<void(size_t, size_t, double)> progress;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

struct MapperSummary {
  bool success = false;
  std::string message;  // why it failed, one line
  image_t initial_image_id1 = kInvalidImageId;
  image_t initial_image_id2 = kInvalidImageId;
  bool initial_calibration_degenerate = false;
  bool initial_focal_from_prior = false;  // degenerate: the pair's focal lengths were held
  double initial_focal_scale = 1.0;       // of the priors, chosen by SelectDegenerateFocal
  size_t num_registered = 0;
  size_t num_images = 0;
  size_t num_local_ba = 0;
  size_t num_global_ba = 0;
  size_t num_global_ba_iterations = 0;     // of all global adjustments together
  size_t num_two_view_points_removed = 0;  // by the filter after the final adjustment
  size_t num_relaxed_registrations = 0;    // images registered at the relaxed thresholds
  double seconds_initialization = 0;
  double seconds_registration = 0;
  double seconds_triangulation = 0;
  double seconds_local_ba = 0;
  double seconds_global_ba = 0;
};

class IncrementalMapper {
 public:
  // `graph` holds the verified matches of the pairs that are not planar/panoramic;
  // `excluded_initial_pairs` lists pairs never to start from (homography-explained).
  IncrementalMapper(const CorrespondenceGraph& graph,
                    std::vector<std::pair<image_t, image_t>> excluded_initial_pairs,
                    IncrementalMapperOptions options);

  // `reconstruction` holds every image (unregistered) with its 2D points and a camera whose
  // width/height and initial focal length are set. On return the registered images have poses
  // and intrinsics, and the 3D points their tracks.
  MapperSummary Reconstruct(Reconstruction* reconstruction);

 private:
  // The pair's F and its inlier matches: verification's (from the graph), else by LO-RANSAC.
  struct PairGeometry {
    bool success = false;
    Eigen::Matrix3d F;
    FeatureMatches inlier_matches;
    bool well_conditioned = false;  // Bougnoux's closed form can be trusted for this pair
  };
  PairGeometry EstimatePairGeometry(const Reconstruction& rec,
                                    const InitialPairCandidate& pair) const;
  // `accept_degenerate`: whether a pair whose self-calibration is flagged degenerate is used.
  // A degenerate pair's focal lengths are held at `focal_scale` x their priors; `adjust`:
  // whether the two-view bundle adjustment runs (a trial of SelectDegenerateFocal skips it).
  bool Initialize(Reconstruction* rec, const InitialPairCandidate& pair,
                  const PairGeometry& geometry, bool accept_degenerate, MapperSummary* summary,
                  double focal_scale = 1.0, bool adjust = true);
  // Re-initialises `rec` (the pair initialised at scale 1; `empty`: the model before) at the
  // scale of the pair's prior focal lengths that a third view fits best.
  void SelectDegenerateFocal(const Reconstruction& empty, const InitialPairCandidate& pair,
                             const PairGeometry& geometry, Reconstruction* rec,
                             MapperSummary* summary);
  // Chooses and initialises the initial pair (the first candidate whose self-calibration is not
  // degenerate, else the best degenerate one); on failure says why in summary->message.
  bool InitializeModel(Reconstruction* rec, MapperSummary* summary);
  // Registers the image (image_registration.h) with `options` (the mapper's, or their Relaxed())
  // and adds its neighbours to frontier_.
  bool RegisterImage(Reconstruction* rec, image_t image_id,
                     const ImageRegistrationOptions& options);
  // Mean truncated squared reprojection error (px^2) of the 2D-3D correspondences of registered
  // image `probe` (MSAC's cost), infinity when it has none.
  double TruncatedRegistrationError(const Reconstruction& rec, image_t probe) const;
  // Registers the next images one by one, each followed by the adjustment the schedule says;
  // failed ones are retried after later successes. When none registers, the candidates are
  // tried once more at the relaxed thresholds (ImageRegistrationOptions::Relaxed).
  void RegisterAll(Reconstruction* rec, MapperSummary* summary);
  // The unregistered images of the frontier that see enough reconstructed points, best first.
  std::vector<image_t> NextImageCandidates(const Reconstruction& rec,
                                           const VisiblePointCounts& counts) const;
  // Adds the matching-graph neighbours of an image just registered to frontier_.
  void ExtendFrontier(image_t registered);
  void LocalBundleAdjustment(Reconstruction* rec, MapperSummary* summary);
  // `max_point_observations` > 0: each point enters with at most that many of its observations
  // (BundleAdjustmentConfig::max_point_observations; the adjustments while the model grows).
  void GlobalBundleAdjustment(Reconstruction* rec, MapperSummary* summary, bool retriangulate,
                              int max_iterations, double function_tolerance,
                              size_t max_point_observations = 0);

  const CorrespondenceGraph& graph_;
  std::vector<std::pair<image_t, image_t>> excluded_initial_pairs_;
  IncrementalMapperOptions options_;
  std::vector<image_t> registration_order_;
  // Every image that matches an image ever registered (a superset of the images that can
  // register next): NextImageCandidates scans these, not every image of the model, which on a
  // 1000-image sequence is the few dozen next to the registered ones.
  std::set<image_t> frontier_;
};

}  // namespace varsfm
