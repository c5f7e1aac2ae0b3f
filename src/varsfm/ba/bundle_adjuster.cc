#include "varsfm/ba/bundle_adjuster.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <thread>

#include <ceres/ceres.h>

#include "varsfm/ba/reprojection_cost.h"
#include "varsfm/util/timer.h"

namespace varsfm {
namespace {

using Solver = BundleAdjustmentOptions::Solver;

// The linear solver for a problem with `num_images` variable poses.
//
// Measured so far (bench/ba_bench.cc: 30 images, 15,000 points, 450,000 observations, f/k1/k2
// free per image, 2-core box under load average 6.6): DENSE_SCHUR 79-82 s wall (28 s CPU),
// 14 iterations, final RMS 0.69 px. The sparse and iterative runs did not finish within the
// session, so the thresholds below are Ceres' guidance, not yet a measured comparison: with up to
// ~100 images the reduced camera system is at most 1300 x 1300 and dense, so DENSE_SCHUR is
// cheapest and the Schur elimination of the points dominates; the dense factorisation grows as (13
// n)^3 and loses beyond that, where the camera graph of an incremental reconstruction is sparse and
// SPARSE_SCHUR with SuiteSparse (CHOLMOD, supernodal) is Ceres' fastest backend (Eigen's simplicial
// LDLT when Ceres lacks SuiteSparse); ITERATIVE_SCHUR only pays off when the reduced system no
// longer fits a direct factorisation.
Solver ChooseSolver(size_t num_images) {
  if (num_images <= 100) return Solver::kDenseSchur;
  if (num_images <= 5000) {
    return ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::SUITE_SPARSE)
               ? Solver::kSparseSchurSuiteSparse
               : Solver::kSparseSchurEigen;
  }
  return Solver::kIterativeSchur;
}

std::string ConfigureLinearSolver(Solver solver, ceres::Solver::Options* options) {
  switch (solver) {
    case Solver::kAuto:
    case Solver::kDenseSchur:
      options->linear_solver_type = ceres::DENSE_SCHUR;
      return "DENSE_SCHUR";
    case Solver::kSparseSchurSuiteSparse:
      options->linear_solver_type = ceres::SPARSE_SCHUR;
      options->sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
      return "SPARSE_SCHUR (SUITE_SPARSE)";
    case Solver::kSparseSchurEigen:
      options->linear_solver_type = ceres::SPARSE_SCHUR;
      options->sparse_linear_algebra_library_type = ceres::EIGEN_SPARSE;
      return "SPARSE_SCHUR (EIGEN_SPARSE)";
    case Solver::kIterativeSchur:
      options->linear_solver_type = ceres::ITERATIVE_SCHUR;
      options->preconditioner_type = ceres::SCHUR_JACOBI;
      return "ITERATIVE_SCHUR (SCHUR_JACOBI)";
  }
  return "";
}

ceres::LossFunction* MakeLoss(const BundleAdjustmentOptions& options) {
  switch (options.loss) {
    case BundleAdjustmentOptions::Loss::kTrivial:
      return nullptr;
    case BundleAdjustmentOptions::Loss::kHuber:
      return new ceres::HuberLoss(options.loss_scale_px);
    case BundleAdjustmentOptions::Loss::kCauchy:
      return new ceres::CauchyLoss(options.loss_scale_px);
  }
  return nullptr;
}

// The indices of the camera block the options hold.
std::vector<int> HeldIntrinsics(const IntrinsicsOptions& o) {
  std::vector<int> held;
  if (!o.refine_focal) held.push_back(Camera::kFocal);
  if (!o.refine_aspect) held.push_back(Camera::kAspect);
  if (!o.refine_skew) held.push_back(Camera::kSkew);
  if (!o.refine_principal_point) {
    held.push_back(Camera::kU0);
    held.push_back(Camera::kV0);
  }
  if (!o.refine_k1) held.push_back(Camera::kK1);
  if (!o.refine_k2) held.push_back(Camera::kK2);
  return held;
}

struct Observation {
  image_t image_id;
  point2D_t point2D_idx;
  point3D_t point3D_id;
};

double RmsError(const Reconstruction& rec, const std::vector<Observation>& observations) {
  if (observations.empty()) return 0.0;
  double sum = 0.0;
  for (const auto& o : observations)
    sum += rec.SquaredReprojectionError({o.image_id, o.point2D_idx}, rec.point3D(o.point3D_id).xyz);
  return std::sqrt(sum / observations.size());
}

// The residuals of the problem: every observation, by an image of the config, of every point
// a variable-pose image observes; points seen fewer than twice in the problem are skipped.
std::vector<Observation> CollectObservations(const BundleAdjustmentConfig& config,
                                             const Reconstruction& rec) {
  std::set<point3D_t> point_ids;
  for (const image_t id : config.variable_pose_images)
    for (const Point2D& p : rec.image(id).points2D)
      if (p.HasPoint3D()) point_ids.insert(p.point3D_id);
  std::vector<Observation> observations;
  for (const point3D_t pid : point_ids) {
    const size_t begin = observations.size();
    for (const TrackElement& el : rec.point3D(pid).track)
      if (config.variable_pose_images.count(el.image_id) ||
          config.constant_pose_images.count(el.image_id))
        observations.push_back({el.image_id, el.point2D_idx, pid});
    if (observations.size() - begin < 2) observations.resize(begin);
  }
  return observations;
}

// Holds the gauge (see bundle_adjuster.h) by making pose blocks constant or partly constant.
void FixGauge(const BundleAdjustmentConfig& config, const std::set<image_t>& problem_images,
              Reconstruction* rec, ceres::Problem* problem) {
  std::vector<image_t> constant, variable;
  for (const image_t id : problem_images)
    (config.variable_pose_images.count(id) ? variable : constant).push_back(id);
  if (constant.size() >= 2 || variable.empty()) return;
  if (constant.empty()) {
    constant.push_back(variable.front());
    variable.erase(variable.begin());
    Rigid3d& pose = rec->image(constant.front()).cam_from_world;
    problem->SetParameterBlockConstant(pose.rotation.coeffs().data());
    problem->SetParameterBlockConstant(pose.translation.data());
  }
  if (variable.empty()) return;
  const Eigen::Vector3d c0 = rec->image(constant.front()).Center();
  Rigid3d& pose = rec->image(variable.front()).cam_from_world;
  const Eigen::Vector3d d = pose.rotation * (pose.Center() - c0);
  int k = 0;
  d.cwiseAbs().maxCoeff(&k);
  problem->SetManifold(pose.translation.data(), new ceres::SubsetManifold(3, {k}));
}

}  // namespace

BundleAdjustmentConfig BundleAdjustmentConfig::Global(const Reconstruction& reconstruction) {
  BundleAdjustmentConfig config;
  for (const image_t id : reconstruction.RegisteredImageIds())
    config.variable_pose_images.insert(id);
  return config;
}

BundleAdjustmentConfig BundleAdjustmentConfig::Local(const Reconstruction& reconstruction,
                                                     const std::vector<image_t>& variable_images) {
  BundleAdjustmentConfig config;
  config.variable_pose_images.insert(variable_images.begin(), variable_images.end());
  std::set<camera_t> variable_cameras;
  for (const image_t id : variable_images) {
    const Image& image = reconstruction.image(id);
    variable_cameras.insert(image.camera_id);
    for (const Point2D& p : image.points2D) {
      if (!p.HasPoint3D()) continue;
      for (const TrackElement& el : reconstruction.point3D(p.point3D_id).track)
        if (!config.variable_pose_images.count(el.image_id) &&
            reconstruction.image(el.image_id).registered)
          config.constant_pose_images.insert(el.image_id);
    }
  }
  for (const image_t id : config.constant_pose_images) {
    const camera_t camera_id = reconstruction.image(id).camera_id;
    if (!variable_cameras.count(camera_id)) config.constant_cameras.insert(camera_id);
  }
  return config;
}

BundleAdjustmentSummary RunBundleAdjustment(const BundleAdjustmentOptions& options,
                                            const BundleAdjustmentConfig& config,
                                            Reconstruction* reconstruction) {
  const Timer timer;
  Reconstruction& rec = *reconstruction;
  BundleAdjustmentSummary result;
  const std::vector<Observation> observations = CollectObservations(config, rec);
  result.num_residuals = static_cast<int>(observations.size());
  if (observations.empty()) return result;
  result.initial_rms_px = RmsError(rec, observations);

  ceres::Problem problem;  // takes ownership of costs, the shared loss and manifolds
  ceres::LossFunction* loss = MakeLoss(options);
  std::set<image_t> problem_images;
  std::set<camera_t> problem_cameras;
  std::set<point3D_t> problem_points;
  for (const Observation& o : observations) {
    Image& image = rec.image(o.image_id);
    Rigid3d& pose = image.cam_from_world;
    if (problem_images.insert(o.image_id).second && config.variable_pose_images.count(o.image_id))
      pose.rotation.normalize();  // the quaternion manifold assumes a unit quaternion
    problem_cameras.insert(image.camera_id);
    problem_points.insert(o.point3D_id);
    problem.AddResidualBlock(ReprojectionCost::Create(image.points2D[o.point2D_idx].xy), loss,
                             rec.camera(image.camera_id).params.data(),
                             pose.rotation.coeffs().data(), pose.translation.data(),
                             rec.point3D(o.point3D_id).xyz.data());
  }

  for (const image_t id : problem_images) {
    Rigid3d& pose = rec.image(id).cam_from_world;
    problem.SetManifold(pose.rotation.coeffs().data(), new ceres::EigenQuaternionManifold);
    if (!config.variable_pose_images.count(id)) {
      problem.SetParameterBlockConstant(pose.rotation.coeffs().data());
      problem.SetParameterBlockConstant(pose.translation.data());
    }
  }
  FixGauge(config, problem_images, &rec, &problem);

  const std::vector<int> held = HeldIntrinsics(options.intrinsics);
  for (const camera_t id : problem_cameras) {
    double* params = rec.camera(id).params.data();
    if (config.constant_cameras.count(id) || held.size() == Camera::kNumParams)
      problem.SetParameterBlockConstant(params);
    else if (!held.empty())
      problem.SetManifold(params, new ceres::SubsetManifold(Camera::kNumParams, held));
  }
  for (const point3D_t id : problem_points)
    if (config.constant_points.count(id))
      problem.SetParameterBlockConstant(rec.point3D(id).xyz.data());

  ceres::Solver::Options solver_options;
  solver_options.minimizer_type = ceres::TRUST_REGION;
  solver_options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.function_tolerance = options.function_tolerance;
  solver_options.gradient_tolerance = options.gradient_tolerance;
  solver_options.parameter_tolerance = options.parameter_tolerance;
  solver_options.num_threads = options.num_threads > 0
                                   ? options.num_threads
                                   : std::max(1u, std::thread::hardware_concurrency());
  solver_options.minimizer_progress_to_stdout = options.verbose;
  solver_options.logging_type = options.verbose ? ceres::PER_MINIMIZER_ITERATION : ceres::SILENT;
  const Solver solver = options.solver == Solver::kAuto
                            ? ChooseSolver(config.variable_pose_images.size())
                            : options.solver;
  result.solver = ConfigureLinearSolver(solver, &solver_options);
  // Schur ordering: points are eliminated first, then cameras and poses.
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  for (const point3D_t id : problem_points)
    ordering->AddElementToGroup(rec.point3D(id).xyz.data(), 0);
  for (const image_t id : problem_images) {
    Rigid3d& pose = rec.image(id).cam_from_world;
    ordering->AddElementToGroup(pose.rotation.coeffs().data(), 1);
    ordering->AddElementToGroup(pose.translation.data(), 1);
  }
  for (const camera_t id : problem_cameras)
    ordering->AddElementToGroup(rec.camera(id).params.data(), 1);
  solver_options.linear_solver_ordering = ordering;

  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  if (options.verbose) std::printf("%s\n", summary.FullReport().c_str());

  for (const image_t id : config.variable_pose_images)
    if (problem_images.count(id)) rec.image(id).cam_from_world.rotation.normalize();
  result.success = summary.IsSolutionUsable();
  result.iterations = summary.num_successful_steps + summary.num_unsuccessful_steps;
  result.final_rms_px = RmsError(rec, observations);
  result.report = summary.BriefReport();
  result.seconds = timer.Seconds();
  return result;
}

}  // namespace varsfm
