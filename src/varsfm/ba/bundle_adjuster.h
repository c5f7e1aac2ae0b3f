#pragma once
// Bundle adjustment (El Hazzat et al., eqs. 34-36): minimises the sum of robustified squared
// reprojection errors over the intrinsics of every image's camera (f, aspect, skew, principal
// point, k1, k2 - each can be held), the poses and the 3D points, with Ceres.
//
// Parameter sharing: images pointing at the same camera_id share one 7-parameter block, so
// "one camera for all images" and "one camera per image" (varying intrinsics) are the same code;
// IntrinsicsOptions::shared_per_size adds one block per image size for the parameters it names.
// A camera that only one image of the problem uses goes into one block with that image's pose
// (ReprojectionBlocks::kImage): Ceres' Schur elimination works block pair by block pair, and one
// block per image instead of three (camera, rotation, translation) makes its elimination about
// twice as fast with the same result (docs/measurements.md).
//
// Determinism: the parameters are copied into one contiguous buffer in id order before solving
// and back afterwards. Ceres orders the blocks of each elimination group by address, so with the
// blocks at their reconstruction's (heap) addresses the order, and the rounding of the solver's
// sums, changed from run to run; in the buffer it is the same in every run. The native solver
// (schur_solver.h) sums in a fixed order with any number of threads; with more than one
// thread Ceres accumulates in a scheduling-dependent order, so its solvers run on one thread
// unless asked for more.
//
// Gauge (the 7-dof similarity ambiguity of a projective-metric reconstruction): when fewer than
// two images of the problem have a constant pose and fewer than three points are constant,
// RunBundleAdjustment fixes it itself:
//  - no constant pose: the pose of the variable image nearest the centroid of their centres is
//    held (6 dof), so that no image is farther from it than the model's radius;
//  - then, with one constant pose C0 (given or just chosen), the scale is held by fixing the
//    coordinate k of the centre C2 of the variable image farthest from C0 (poses are optimised
//    as rotation and centre) that changes most under a scaling about C0: argmax_k
//    |(C2 - C0)_k|. Two or more constant poses fix the gauge on their own.
#include <set>
#include <string>
#include <vector>

#include "varsfm/scene/reconstruction.h"
#include "varsfm/util/enum_names.h"
#include "varsfm/util/types.h"

namespace varsfm {

// Which of the camera parameters [f, aspect, skew, u0, v0, k1, k2] are refined; the others are
// held through a ceres::SubsetManifold on the camera block (constant block when all are held).
struct IntrinsicsOptions {
  bool refine_focal = true;
  bool refine_aspect = false;
  bool refine_skew = false;
  bool refine_principal_point = false;
  bool refine_k1 = true;
  bool refine_k2 = true;
  // Parameters (Camera::Param indices) estimated once per image size: all variable cameras of
  // that size take them from one shared block, the rest from their own. The refine_* flags
  // above say which are free, wherever they live. {kU0, kV0} with refine_principal_point is
  // the mapper's default: one image cannot separate its principal point from its rotation
  // (docs/mapper.md: refined per image it costs 2.3 deg on fountain-P11), but the images of
  // one physical camera share it, and many views pin it down. {kAspect, kSkew, kU0, kV0, kK1,
  // kK2} is "focal length per image, the rest shared". Sizes whose variable cameras fewer than
  // `min_images_to_share` of the problem's images use form no group: there the shared
  // parameters are held. One camera of many images (`--intrinsics shared`) forms a group.
  std::vector<int> shared_per_size;
  int min_images_to_share = 3;
  // A camera zoomed in shares them only with those of its size whose focal lengths are within
  // this ratio of each other (a zoom band; 0: every camera of the size). A zoom moves the
  // principal point (a centred crop scales its offset from the image centre with the focal
  // length) and changes the distortion, and the one point of a size pooled over zoomed and
  // unzoomed photos is wrong for both (docs/measurements.md, "The principal point under zoom").
  double max_shared_focal_ratio = 0.0;
};

// The camera parameters (Camera::Param indices, ascending) that `options` holds at their values.
std::vector<int> HeldIntrinsics(const IntrinsicsOptions& options);

struct BundleAdjustmentOptions {
  enum class Loss { kTrivial, kHuber, kCauchy };
  // How the normal equations are solved; kAuto chooses by problem size (see ChooseSolver in
  // bundle_adjuster.cc for the measurements behind the choice).
  enum class Solver {
    kAuto,
    kDenseSchur,
    kSparseSchurSuiteSparse,
    kSparseSchurEigen,
    kIterativeSchur,
    // The project's own Levenberg-Marquardt with the Schur complement of the points
    // (schur_solver.h): the same model and reduced system as Ceres' DENSE_SCHUR /
    // SPARSE_SCHUR without Ceres' per-block overhead. kAuto's choice up to 5000 images.
    kNativeDenseSchur,
    // Ceres only, chosen by size (DENSE_SCHUR up to 250 images, SPARSE_SCHUR beyond): the
    // reference the native solver is measured against.
    kCeresAuto,
  };

  // Cauchy by default: on inlier-only data it reaches the same noise floor and focal accuracy
  // as the plain squared loss, and with 5 % gross outliers it keeps the focal error near the
  // clean value where the squared loss is pulled off (tests/ba/bundle_adjuster_test.cc).
  Loss loss = Loss::kCauchy;
  double loss_scale_px = 1.0;  // residual (px) where the robust loss starts to flatten
  int max_iterations = 100;
  double function_tolerance = 1e-6;
  double gradient_tolerance = 1e-10;
  double parameter_tolerance = 1e-8;
  // 0: every core for the native solver, whose result does not depend on the number of threads,
  // and one thread for Ceres' solvers, whose multi-threaded results do (see above); n > 0: n
  // threads for either (docs/measurements.md: what a second thread gains).
  int num_threads = 0;
  Solver solver = Solver::kAuto;
  // Levenberg-Marquardt, or Powell's dogleg (for the native solver and Ceres' alike); the
  // mapper's global adjustments use the dogleg (incremental_mapper.h has the measurements).
  enum class TrustRegion { kLevenbergMarquardt, kDogleg };
  TrustRegion trust_region = TrustRegion::kLevenbergMarquardt;
  // > 0: the native solver solves a sparse reduced system of at least this many images
  // (reduced-system blocks) by preconditioned conjugate gradients instead of a factorisation
  // (SchurSolverOptions::iterative_min_blocks).
  int iterative_min_images = 0;
  double iterative_tolerance = 1e-6;  // SchurSolverOptions::iterative_tolerance
  int iterative_max_iterations = 500;
  IntrinsicsOptions intrinsics;
  bool verbose = false;  // Ceres progress to stdout
};

// The names `--ba-solver` takes.
inline constexpr EnumName<BundleAdjustmentOptions::Solver> kBundleAdjustmentSolverNames[] = {
    {BundleAdjustmentOptions::Solver::kAuto, "auto"},
    {BundleAdjustmentOptions::Solver::kNativeDenseSchur, "native"},
    {BundleAdjustmentOptions::Solver::kCeresAuto, "ceres"},
    {BundleAdjustmentOptions::Solver::kDenseSchur, "dense"},
    {BundleAdjustmentOptions::Solver::kSparseSchurSuiteSparse, "sparse"},
    {BundleAdjustmentOptions::Solver::kSparseSchurEigen, "sparse-eigen"},
    {BundleAdjustmentOptions::Solver::kIterativeSchur, "iterative"}};

// The names `--global-ba-trust-region` takes.
inline constexpr EnumName<BundleAdjustmentOptions::TrustRegion> kTrustRegionNames[] = {
    {BundleAdjustmentOptions::TrustRegion::kDogleg, "dogleg"},
    {BundleAdjustmentOptions::TrustRegion::kLevenbergMarquardt, "lm"}};

// What enters the problem. A 3D point enters when a variable-pose image observes it; then every
// observation of it by an image of the config (variable or constant pose) is a residual. Points
// with fewer than two residuals are left out (a single ray does not fix a point). A constant
// point enters only through its observations by variable-pose images (each one fixes a pose).
struct BundleAdjustmentConfig {
  std::set<image_t> variable_pose_images;
  std::set<image_t> constant_pose_images;
  std::set<camera_t> constant_cameras;
  std::set<point3D_t> constant_points;
  // > 0: a variable point with more residuals than this enters with this many of them only,
  // spread evenly over its track from an offset that varies with the point. On a set that
  // densifies, the Schur elimination costs one block product per pair of a point's observations
  // (sum of squared track lengths) and the reduced system has a block per image pair sharing a
  // point; a subset of each long track keeps every image constrained by its short tracks and part
  // of its long ones. For the adjustments while the model grows, not the final one
  // (BundleAdjustmentScheduleOptions::growth_ba_max_point_observations).
  size_t max_point_observations = 0;

  // Every registered image with a variable pose; the gauge is fixed by RunBundleAdjustment.
  static BundleAdjustmentConfig Global(const Reconstruction& reconstruction);
  // The given images' poses and intrinsics free, every point they observe free, and every other
  // registered image that observes those points included with constant pose and constant
  // camera. A camera shared with a variable image stays free (sharing wins over holding).
  // With max_track_length > 0, a point seen by more images than that is held constant instead
  // and brings in no other image (as COLMAP's local adjustment leaves long tracks out): it is
  // already well determined, and on a long sequence whose points stay in view for many images
  // its whole track would make every local adjustment grow with the model (bench/scale).
  static BundleAdjustmentConfig Local(const Reconstruction& reconstruction,
                                      const std::vector<image_t>& variable_images,
                                      size_t max_track_length = 0);
};

struct BundleAdjustmentSummary {
  bool success = false;  // Ceres returned a usable solution (converged or hit an iteration limit)
  int iterations = 0;
  double initial_rms_px = 0.0;  // plain (not robustified) RMS over the problem's residuals
  double final_rms_px = 0.0;
  int num_residuals = 0;  // observations in the problem (each gives two scalar residuals)
  double seconds = 0.0;
  std::string solver;  // e.g. "SPARSE_SCHUR (SUITE_SPARSE)"
  std::string report;  // Ceres' one-line report
};

// Optimises `reconstruction` in place. Returns success = false (and leaves the reconstruction
// untouched) when the config yields no residual.
BundleAdjustmentSummary RunBundleAdjustment(const BundleAdjustmentOptions& options,
                                            const BundleAdjustmentConfig& config,
                                            Reconstruction* reconstruction);

}  // namespace varsfm
