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
#include <cstdint>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include "varsfm/ba/bundle_adjuster.h"
#include "varsfm/scene/reconstruction.h"
#include "varsfm/sfm/correspondence_graph.h"
#include "varsfm/sfm/initial_pair.h"
#include "varsfm/util/random.h"

namespace varsfm {

struct IncrementalMapperOptions {
  InitialPairOptions initial_pair;
  int max_initial_pair_trials = 10;
  int min_initial_points = 50;
  // The initial pair's points must have this median triangulation angle: a pure rotation or
  // a too-short baseline gives near-zero angles (and a meaningless structure).
  double init_min_median_angle_deg = 3.0;

  int local_ba_images = 3;  // m0 of the paper
  // Beyond the paper: in a local adjustment, points seen by more images than this are held and
  // enter only through the window's observations (0: every point free with its whole track). As
  // COLMAP (15); it keeps the local adjustments' cost bounded on long sequences (bench/scale).
  int local_ba_max_track_length = 15;
  // Local adjustments stop at this relative cost decrease (Ceres' function tolerance): they
  // only need to keep the new images consistent, the global ones reach the minimum.
  double local_ba_function_tolerance = 1e-3;
  double global_ba_function_tolerance = 1e-5;
  // The growth adjustments' (global_ba_growth) tolerance: each is followed by others and by
  // the final one, so they stop earlier. On bench/scale's street (sequential order, 2026-12-02)
  // 1e-5 -> 1e-4: 1000 images global adjustments 51.8 -> 44.3 s, 500: 22.3 -> 19.9 s, the
  // 300-image orbit 24.8 -> 19.0 s; camera-centre, rotation and focal errors the same to 1 %
  // (the final adjustment stays at global_ba_function_tolerance).
  double growth_ba_function_tolerance = 1e-4;
  // The global adjustments' trust region. The dogleg by default: on bench/scale's 1000-image
  // street the final adjustment from the same start (2026-12-02) took 17 steps, 12
  // factorisations and 22 s against Levenberg-Marquardt's 21, 21 and 31 s, and ended nearer the
  // minimum (camera-centre error 0.17 against 0.30 GT units). LM's damping held back the weak
  // directions (per-image distortion against pose, the street's bend); a rejected dogleg step
  // reuses its factorisation. The local adjustments (3 steps) stay on LM.
  BundleAdjustmentOptions::TrustRegion global_ba_trust_region =
      BundleAdjustmentOptions::TrustRegion::kDogleg;
  // Iteration caps: the global adjustments while the model grows, and the final one. With LM
  // some global adjustments of a 1000-image street sequence (bench/scale) crawled along its
  // weak directions at ~1e-4 relative decrease per iteration to the cap; those during growth
  // are followed by others, so 25 bounds their cost (with the dogleg they take 5-8 steps).
  int global_ba_max_iterations = 25;
  // After a degenerate initial pair (focal lengths held in its two-view adjustment), a global
  // adjustment when this many images are registered (0: none).
  int degenerate_init_global_ba_images = 4;
  // A degenerate initial pair's focal length is chosen by a third view (SelectDegenerateFocal
  // in incremental_mapper.cc) instead of taken from the prior.
  bool degenerate_init_focal_search = true;
  int final_global_ba_max_iterations = 50;
  int first_global_ba_images = 13;  // M0 of the paper (10..20)
  // Beyond the paper: a further global BA each time the model has grown by this factor since
  // the last one (0 disables: the paper's schedule).
  double global_ba_growth = 1.4;
  // The paper's global adjustment at the end; off (with no M0 / growth adjustments) gives the
  // local-only, Mouragnon-like baseline of the benchmarks.
  bool final_global_ba = true;

  int min_correspondences = 6;  // n0: the DLT needs six 2D-3D correspondences
  int min_registration_inliers = 15;
  double registration_max_error_px = 4.0;
  double triangulation_max_error_px = 4.0;
  double filter_max_error_px = 4.0;
  double min_triangulation_angle_deg = 1.5;

  // Which intrinsics are estimated per image (the others stay at their initial values:
  // principal point at the image centre, aspect 1, skew 0). The paper refines them all; on
  // real sequences holding the principal point, aspect and skew is more accurate (see
  // docs/mapper.md).
  bool refine_principal_point = false;
  // One principal point per image size, estimated in the global adjustments from all images
  // of that size (IntrinsicsOptions::share_principal_point); new images start from it.
  bool share_principal_point = true;
  // "Focal length per image, the rest shared": aspect, skew, principal point and k1, k2 are
  // one set per image size (a zoom lens on one body), estimated in the global adjustments.
  bool share_all_but_focal = false;
  bool refine_aspect = false;
  bool refine_skew = false;
  bool refine_distortion = true;

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
  size_t num_global_ba_iterations = 0;  // of all global adjustments together
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
  // The pair's verified matches re-verified by F (LO-RANSAC): F and its inlier matches.
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
  // A 2D point of an unregistered image and the 3D point its tracks lead to.
  struct Correspondence2D3D {
    point2D_t point2D_idx;
    point3D_t point3D_id;
  };
  // Through tracks (Algorithm 2 of the paper, generalised to every registered image).
  std::vector<Correspondence2D3D> Correspondences(const Reconstruction& rec,
                                                  image_t image_id) const;
  bool RegisterImage(Reconstruction* rec, image_t image_id);
  size_t TriangulateImage(Reconstruction* rec, image_t image_id);
  std::vector<image_t> NextImageCandidates(const Reconstruction& rec) const;
  // Adds the matching-graph neighbours of an image just registered to frontier_.
  void ExtendFrontier(image_t registered);
  void LocalBundleAdjustment(Reconstruction* rec, MapperSummary* summary);
  void GlobalBundleAdjustment(Reconstruction* rec, MapperSummary* summary, bool retriangulate,
                              int max_iterations, double function_tolerance);

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
