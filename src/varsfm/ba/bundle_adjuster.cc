#include "varsfm/ba/bundle_adjuster.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <map>
#include <memory>
#include <thread>

#include <ceres/ceres.h>

#include "varsfm/ba/analytic_reprojection_cost.h"
#include "varsfm/ba/intrinsics_groups.h"
#include "varsfm/ba/schur_solver.h"
#include "varsfm/util/error.h"
#include "varsfm/util/timer.h"

#include <fmt/format.h>

namespace varsfm {
namespace {

using Solver = BundleAdjustmentOptions::Solver;

// The linear solver for a problem with `num_images` variable poses: the project's own
// Levenberg-Marquardt / dogleg with the points' Schur complement (schur_solver.h; dense, or sparse
// for a banded camera graph) reaches the same iterations and minimum as Ceres' DENSE_SCHUR and
// SPARSE_SCHUR in less time; Ceres' ITERATIVE_SCHUR stays for problems beyond 5000 images, where
// no direct factorisation fits. The measurements behind both choices: docs/measurements.md.
Solver ChooseSolver(size_t num_images) {
  if (num_images <= 5000) return Solver::kNativeDenseSchur;
  return Solver::kIterativeSchur;
}

// Ceres' linear solver by size (kCeresAuto), as chosen before the native solver (see above).
Solver ChooseCeresSolver(size_t num_images) {
  if (num_images <= 250) return Solver::kDenseSchur;
  if (num_images <= 5000)
    return ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::SUITE_SPARSE)
               ? Solver::kSparseSchurSuiteSparse
               : Solver::kSparseSchurEigen;
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
    case Solver::kNativeDenseSchur:
      return "NATIVE_DENSE_SCHUR";
    case Solver::kCeresAuto:
      break;  // resolved by ChooseSolver
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

// The camera parameters the options hold, bit i for parameter i.
unsigned HeldIntrinsicsMask(const IntrinsicsOptions& o) {
  unsigned held = 0;
  const auto hold_if = [&held](bool hold, int param) { held |= hold ? 1u << param : 0u; };
  hold_if(!o.refine_focal, Camera::kFocal);
  hold_if(!o.refine_aspect, Camera::kAspect);
  hold_if(!o.refine_skew, Camera::kSkew);
  hold_if(!o.refine_principal_point, Camera::kU0);
  hold_if(!o.refine_principal_point, Camera::kV0);
  hold_if(!o.refine_k1, Camera::kK1);
  hold_if(!o.refine_k2, Camera::kK2);
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
  std::vector<point3D_t> point_ids;  // ascending, each once
  for (const image_t id : config.variable_pose_images)
    for (const Point2D& p : rec.image(id).points2D)
      if (p.HasPoint3D()) point_ids.push_back(p.point3D_id);
  std::sort(point_ids.begin(), point_ids.end());
  point_ids.erase(std::unique(point_ids.begin(), point_ids.end()), point_ids.end());
  std::vector<Observation> observations;
  for (const point3D_t pid : point_ids) {
    const size_t begin = observations.size();
    const bool constant = config.constant_points.count(pid) > 0;
    for (const TrackElement& el : rec.point3D(pid).track)
      if (config.variable_pose_images.count(el.image_id) ||
          (!constant && config.constant_pose_images.count(el.image_id)))
        observations.push_back({el.image_id, el.point2D_idx, pid});
    const size_t count = observations.size() - begin;
    if (!constant && count < 2) observations.resize(begin);
    const size_t cap = config.max_point_observations;
    if (!constant && cap >= 2 && count > cap) {
      // Every (count / cap)-th observation from an offset that turns with the point's id
      // (offsets i * count / cap + pid, mod count, are distinct): the same choice for every
      // point of one image sequence would leave the images between the chosen positions with
      // the short tracks only. Kept in track order.
      std::vector<size_t> keep(cap);
      for (size_t i = 0; i < cap; ++i) keep[i] = (i * count / cap + pid) % count;
      std::sort(keep.begin(), keep.end());
      for (size_t i = 0; i < cap; ++i) observations[begin + i] = observations[begin + keep[i]];
      observations.resize(begin + cap);
    }
  }
  return observations;
}

// The problem's parameters, copied into one contiguous buffer laid out in id order so that
// Ceres' address-ordered elimination groups come out the same in every run (see
// bundle_adjuster.h). An image whose camera no other image of the problem uses gets one block,
// [camera (7), quaternion (4), centre (3)] (ReprojectionBlocks::kImage: the Schur
// elimination's cost grows with the square of the blocks per image); otherwise the camera and
// the pose [quaternion, centre] are two blocks. Then the shared per-size blocks, then the
// points.
class ParameterBuffer {
 public:
  // `group_of_camera`: the cameras that take parameters from a shared block, and its key.
  ParameterBuffer(const Reconstruction& rec, const std::set<image_t>& images,
                  const std::map<camera_t, IntrinsicsGroupKey>& group_of_camera,
                  unsigned shared_mask, const std::vector<point3D_t>& points)
      : group_of_camera_(group_of_camera), shared_mask_(shared_mask), point_ids_(points) {
    std::set<IntrinsicsGroupKey> groups;
    for (const auto& [id, key] : group_of_camera) groups.insert(key);
    std::map<camera_t, int> images_of_camera;
    for (const image_t id : images) ++images_of_camera[rec.image(id).camera_id];
    data_.reserve(images.size() * (Camera::kNumParams + 7) + groups.size() * Camera::kNumParams +
                  points.size() * 3);
    const auto add_camera = [&](camera_t id) {
      camera_[id] = data_.size();
      const auto& p = rec.camera(id).params;
      data_.insert(data_.end(), p.begin(), p.end());
    };
    const auto add_pose = [&](image_t id) {
      pose_[id] = data_.size();
      const Rigid3d& pose = rec.image(id).cam_from_world;
      const Eigen::Vector4d q = pose.rotation.normalized().coeffs();  // x, y, z, w
      data_.insert(data_.end(), q.data(), q.data() + 4);
      const Eigen::Vector3d centre = pose.Center();
      data_.insert(data_.end(), centre.data(), centre.data() + 3);
    };
    for (const image_t id : images) {
      const camera_t camera_id = rec.image(id).camera_id;
      if (images_of_camera.at(camera_id) != 1) continue;
      image_block_.insert(id);
      add_camera(camera_id);
      add_pose(id);
    }
    for (const auto& [id, count] : images_of_camera)
      if (count > 1) add_camera(id);
    // A shared block starts at the mean of its cameras' parameters.
    for (const IntrinsicsGroupKey& key : groups) {
      Eigen::Matrix<double, Camera::kNumParams, 1> sum;
      sum.setZero();
      int n = 0;
      for (const auto& [id, count] : images_of_camera) {
        const auto it = group_of_camera.find(id);
        if (it == group_of_camera.end() || it->second != key) continue;
        const Camera& c = rec.camera(id);
        sum += Eigen::Map<const Eigen::Matrix<double, Camera::kNumParams, 1>>(c.params.data());
        ++n;
      }
      group_[key] = data_.size();
      for (int i = 0; i < Camera::kNumParams; ++i) data_.push_back(sum[i] / std::max(n, 1));
    }
    for (const image_t id : images)
      if (!image_block_.count(id)) add_pose(id);
    points_begin_ = data_.size();
    for (const point3D_t id : points) {
      const Eigen::Vector3d& x = rec.point3D(id).xyz;
      data_.insert(data_.end(), x.data(), x.data() + 3);
    }
    initial_ = data_;
  }

  // Whether the image's camera and pose are one block (starting at camera(its camera)).
  bool HasImageBlock(image_t id) const { return image_block_.count(id) > 0; }
  double* camera(camera_t id) { return &data_[camera_.at(id)]; }
  double* pose(image_t id) { return &data_[pose_.at(id)]; }  // quaternion, centre
  double* point(point3D_t id) { return &data_[PointOffset(id)]; }
  double* group(const IntrinsicsGroupKey& key) { return &data_[group_.at(key)]; }
  // The shared block the camera takes parameters from; null when it has none.
  double* group(const Camera& camera) {
    const auto it = group_of_camera_.find(camera.camera_id);
    return it == group_of_camera_.end() ? nullptr : group(it->second);
  }
  const std::map<camera_t, size_t>& cameras() const { return camera_; }
  const std::map<IntrinsicsGroupKey, size_t>& groups() const { return group_; }

  // Writes the optimised values back (the shared principal points into each of their cameras);
  // what the config holds constant is left untouched, bit for bit.
  void CopyTo(const BundleAdjustmentConfig& config, Reconstruction* rec) {
    for (const auto& [id, offset] : camera_) {
      if (config.constant_cameras.count(id)) continue;
      Camera& c = rec->camera(id);
      std::copy_n(&data_[offset], Camera::kNumParams, c.params.begin());
      if (const double* shared = group(c))
        for (int i = 0; i < Camera::kNumParams; ++i)
          if ((shared_mask_ >> i) & 1u) c.params[i] = shared[i];
    }
    for (const auto& [id, offset] : pose_) {
      // Poses the problem held (the config's, or the gauge's) keep their values bit for bit
      // rather than pass through the centre and back.
      if (!config.variable_pose_images.count(id) ||
          std::equal(&data_[offset], &data_[offset] + 7, &initial_[offset]))
        continue;
      Rigid3d& pose = rec->image(id).cam_from_world;
      pose.rotation.coeffs() = Eigen::Map<const Eigen::Vector4d>(&data_[offset]);
      pose.rotation.normalize();
      pose.translation = -(pose.rotation * Eigen::Map<const Eigen::Vector3d>(&data_[offset + 4]));
    }
    for (size_t i = 0; i < point_ids_.size(); ++i)
      if (!config.constant_points.count(point_ids_[i]))
        rec->point3D(point_ids_[i]).xyz =
            Eigen::Map<const Eigen::Vector3d>(&data_[points_begin_ + 3 * i]);
  }

 private:
  size_t PointOffset(point3D_t id) const {
    const auto it = std::lower_bound(point_ids_.begin(), point_ids_.end(), id);
    if (it == point_ids_.end() || *it != id)
      Fail("bundle adjustment: point {} not in the problem", id);
    return points_begin_ + 3 * static_cast<size_t>(it - point_ids_.begin());
  }

  std::vector<double> data_;
  std::vector<double> initial_;  // data_ before solving
  std::set<image_t> image_block_;
  std::map<camera_t, size_t> camera_;
  std::map<IntrinsicsGroupKey, size_t> group_;
  std::map<camera_t, IntrinsicsGroupKey> group_of_camera_;
  unsigned shared_mask_ = 0;
  std::map<image_t, size_t> pose_;
  std::vector<point3D_t> point_ids_;  // ascending; their xyz from points_begin_ on
  size_t points_begin_ = 0;
};

// What of an image's pose the problem holds: nothing, all of it, or (kScale) one coordinate of
// the centre, the one along which the image lies farthest from the gauge image.
struct PoseHold {
  enum Kind { kFree, kConstant, kScale } kind = kFree;
  int coordinate = 0;
};

// Holds the gauge (see bundle_adjuster.h) through the images' pose holds, unless constant
// points in the problem hold it (three or more).
std::map<image_t, PoseHold> PoseHolds(const BundleAdjustmentConfig& config,
                                      const std::set<image_t>& problem_images,
                                      size_t num_constant_points, const Reconstruction& rec) {
  std::map<image_t, PoseHold> holds;
  std::vector<image_t> constant, variable;
  for (const image_t id : problem_images) {
    const bool is_variable = config.variable_pose_images.count(id) > 0;
    (is_variable ? variable : constant).push_back(id);
    holds[id].kind = is_variable ? PoseHold::kFree : PoseHold::kConstant;
  }
  if (constant.size() >= 2 || variable.empty() || num_constant_points >= 3) return holds;
  if (constant.empty()) {
    // The pose held is the one nearest the centroid of the centres: the lever arm from it to
    // any image is then at most the model's radius, not its length.
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (const image_t id : variable) centroid += rec.image(id).Center();
    centroid /= static_cast<double>(variable.size());
    const auto nearest =
        std::min_element(variable.begin(), variable.end(), [&](image_t a, image_t b) {
          return (rec.image(a).Center() - centroid).squaredNorm() <
                 (rec.image(b).Center() - centroid).squaredNorm();
        });
    constant.push_back(*nearest);
    variable.erase(nearest);
    holds[constant.front()].kind = PoseHold::kConstant;
  }
  if (variable.empty()) return holds;
  // The scale through the image farthest from C0: a scaling about C0 moves C by s (C - C0), so
  // holding the largest coordinate of C - C0 holds it, and the longer C - C0, the better
  // conditioned: held through the neighbour of a sequence's end image, 0.1 units from it on a
  // 100-unit street, every scale correction would swing the far end (docs/measurements.md).
  const Eigen::Vector3d c0 = rec.image(constant.front()).Center();
  const auto farthest =
      std::max_element(variable.begin(), variable.end(), [&](image_t a, image_t b) {
        return (rec.image(a).Center() - c0).squaredNorm() <
               (rec.image(b).Center() - c0).squaredNorm();
      });
  const Eigen::Vector3d d = rec.image(*farthest).Center() - c0;
  d.cwiseAbs().maxCoeff(&holds[*farthest].coordinate);
  holds[*farthest].kind = PoseHold::kScale;
  return holds;
}

// The indices of the set bits of `mask` below `size`.
std::vector<int> Bits(unsigned mask, int size) {
  std::vector<int> bits;
  for (int i = 0; i < size; ++i)
    if ((mask >> i) & 1u) bits.push_back(i);
  return bits;
}

// A manifold of `size` parameters of which those in `held` stay constant (Euclidean: none).
std::unique_ptr<ceres::Manifold> Subset(int size, unsigned held) {
  if (held == 0) return std::make_unique<ceres::EuclideanManifold<ceres::DYNAMIC>>(size);
  return std::make_unique<ceres::SubsetManifold>(size, Bits(held, size));
}

// The manifolds of a pose's quaternion (3 degrees of freedom) and centre under `hold`; a held
// pose gets parts with nothing free (used inside an image block whose camera varies).
std::pair<std::unique_ptr<ceres::Manifold>, std::unique_ptr<ceres::Manifold>> PoseManifolds(
    const PoseHold& hold) {
  if (hold.kind == PoseHold::kConstant) return {Subset(4, 0xfu), Subset(3, 0x7u)};
  return {std::make_unique<ceres::EigenQuaternionManifold>(),
          Subset(3, hold.kind == PoseHold::kScale ? 1u << hold.coordinate : 0u)};
}

// A parameter block of the problem and how it is held: constant, or through its manifold (null:
// every parameter free).
struct ParameterBlockSpec {
  double* x = nullptr;
  int size = 0;
  std::unique_ptr<ceres::Manifold> manifold;
  bool constant = false;
};

constexpr unsigned kAllCameraParams = (1u << Camera::kNumParams) - 1;

// A camera block (or a shared per-size block) holding the parameters in `held`.
ParameterBlockSpec CameraBlock(double* x, unsigned held) {
  ParameterBlockSpec spec{x, Camera::kNumParams, nullptr, false};
  if (held == kAllCameraParams)
    spec.constant = true;
  else if (held != 0)
    spec.manifold =
        std::make_unique<ceres::SubsetManifold>(Camera::kNumParams, Bits(held, Camera::kNumParams));
  return spec;
}

// A pose block [quaternion, centre].
ParameterBlockSpec PoseBlock(const PoseHold& hold, double* pose) {
  using Pose =
      ceres::ProductManifold<std::unique_ptr<ceres::Manifold>, std::unique_ptr<ceres::Manifold>>;
  ParameterBlockSpec spec{pose, 7, nullptr, false};
  if (hold.kind == PoseHold::kConstant) {
    spec.constant = true;
  } else {
    auto [rotation, centre] = PoseManifolds(hold);
    spec.manifold = std::make_unique<Pose>(std::move(rotation), std::move(centre));
  }
  return spec;
}

// An image block [camera, quaternion, centre] (held_camera: the camera parameters it holds);
// constant when nothing in it is free.
ParameterBlockSpec ImageBlock(const PoseHold& hold, unsigned held_camera, double* block) {
  using Image =
      ceres::ProductManifold<std::unique_ptr<ceres::Manifold>, std::unique_ptr<ceres::Manifold>,
                             std::unique_ptr<ceres::Manifold>>;
  ParameterBlockSpec spec{block, Camera::kNumParams + 7, nullptr, false};
  if (hold.kind == PoseHold::kConstant && held_camera == kAllCameraParams) {
    spec.constant = true;
  } else {
    auto [rotation, centre] = PoseManifolds(hold);
    spec.manifold = std::make_unique<Image>(Subset(Camera::kNumParams, held_camera),
                                            std::move(rotation), std::move(centre));
  }
  return spec;
}

}  // namespace

std::vector<int> HeldIntrinsics(const IntrinsicsOptions& options) {
  const unsigned held = HeldIntrinsicsMask(options);
  std::vector<int> params;
  for (int i = 0; i < Camera::kNumParams; ++i)
    if ((held >> i) & 1u) params.push_back(i);
  return params;
}

BundleAdjustmentConfig BundleAdjustmentConfig::Global(const Reconstruction& reconstruction) {
  BundleAdjustmentConfig config;
  for (const image_t id : reconstruction.RegisteredImageIds())
    config.variable_pose_images.insert(id);
  return config;
}

BundleAdjustmentConfig BundleAdjustmentConfig::Local(const Reconstruction& reconstruction,
                                                     const std::vector<image_t>& variable_images,
                                                     size_t max_track_length) {
  BundleAdjustmentConfig config;
  config.variable_pose_images.insert(variable_images.begin(), variable_images.end());
  std::set<camera_t> variable_cameras;
  // The images of the variable points' tracks, gathered, then looked up once each: a lookup per
  // observation in the model's and the config's maps was most of this function's time on a set
  // whose tracks grow long.
  std::vector<image_t> track_images;
  for (const image_t id : variable_images) {
    const Image& image = reconstruction.image(id);
    variable_cameras.insert(image.camera_id);
    for (const Point2D& p : image.points2D) {
      if (!p.HasPoint3D()) continue;
      const std::vector<TrackElement>& track = reconstruction.point3D(p.point3D_id).track;
      if (max_track_length > 0 && track.size() > max_track_length) {
        config.constant_points.insert(p.point3D_id);
        continue;
      }
      for (const TrackElement& el : track) track_images.push_back(el.image_id);
    }
  }
  std::sort(track_images.begin(), track_images.end());
  track_images.erase(std::unique(track_images.begin(), track_images.end()), track_images.end());
  for (const image_t id : track_images)
    if (!config.variable_pose_images.count(id) && reconstruction.image(id).registered)
      config.constant_pose_images.insert(id);
  for (const image_t id : config.constant_pose_images) {
    const camera_t camera_id = reconstruction.image(id).camera_id;
    if (!variable_cameras.count(camera_id)) config.constant_cameras.insert(camera_id);
  }
  return config;
}

namespace {

// An adjustment's problem as RunBundleAdjustment assembles it: its parameters (in `buffer`), the
// images and points they belong to, and the loss of every residual.
struct AssembledProblem {
  const BundleAdjustmentOptions& options;
  const std::set<image_t>& images;
  const std::vector<point3D_t>& points;  // ascending
  const std::set<double*>& used_groups;  // the shared per-size blocks in use
  size_t num_observations;
  ParameterBuffer& buffer;
  ceres::LossFunction* loss;
};

// Solves `p` with the project's own Schur-complement solver. `for_each_residual(add)` gives every
// residual with its blocks, `describe_blocks()` every block and how it is held. Returns whether
// the RMS errors in `result` come from the solver's residuals.
template <typename ForEachResidual, typename DescribeBlocks>
bool SolveNatively(const AssembledProblem& p, const ForEachResidual& for_each_residual,
                   const DescribeBlocks& describe_blocks, const Timer& timer,
                   BundleAdjustmentSummary* result) {
  bool rms_from_solver = false;
  result->solver = "NATIVE_DENSE_SCHUR";
  // The blocks go to the solver directly (LeastSquaresProblem), the cost functions one after the
  // other in a deque rather than one heap object each.
  std::deque<AnalyticReprojectionCost> costs;
  LeastSquaresProblem problem;
  problem.Reserve(p.images.size() * 2 + p.points.size(), p.num_observations,
                  p.num_observations * 3);
  for_each_residual([&](const Eigen::Vector2d& xy, ReprojectionBlocks kind,
                        std::optional<unsigned> shared, double* const* blocks, int count) {
    costs.emplace_back(xy, kind, shared);
    problem.AddResidualBlock(&costs.back(), p.loss, blocks, count);
  });
  const std::vector<ParameterBlockSpec> specs = describe_blocks();
  for (const ParameterBlockSpec& spec : specs)
    problem.AddParameterBlock(spec.x, spec.size, spec.manifold.get(), spec.constant);

  SchurSolverOptions native;
  native.max_iterations = p.options.max_iterations;
  native.function_tolerance = p.options.function_tolerance;
  native.gradient_tolerance = p.options.gradient_tolerance;
  native.parameter_tolerance = p.options.parameter_tolerance;
  native.progress_to_stdout = p.options.verbose;
  native.iterative_min_blocks = p.options.iterative_min_images;
  native.iterative_tolerance = p.options.iterative_tolerance;
  native.iterative_max_iterations = p.options.iterative_max_iterations;
  if (p.options.trust_region == BundleAdjustmentOptions::TrustRegion::kDogleg)
    native.trust_region = SchurSolverOptions::TrustRegion::kDogleg;
  native.num_threads = p.options.num_threads > 0
                           ? p.options.num_threads
                           : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::vector<double*> points;
  points.reserve(p.points.size());
  for (const point3D_t id : p.points) points.push_back(p.buffer.point(id));
  const SchurSolverSummary summary = SolveWithSchurComplement(native, points, problem);
  result->success = summary.usable;
  // The RMS from the solver's own residuals (one per observation): two passes over the
  // observations less (they took 3 % of a 100-image sequence's mapping).
  if (summary.usable) {
    rms_from_solver = true;
    result->initial_rms_px = std::sqrt(summary.initial_squared_norm / p.num_observations);
    result->final_rms_px = std::sqrt(summary.final_squared_norm / p.num_observations);
  }
  result->iterations = summary.successful_steps + summary.unsuccessful_steps;
  result->report = fmt::format(
      "native Schur {} ({}, {} columns, {:.2f} full): {} ({} + {} steps, cost {:.6e} -> "
      "{:.6e}; s: setup {:.4f}, "
      "linearise {:.4f}, residuals {:.4f}, solve {:.4f} (factorise {:.4f}); total {:.4f})",
      native.trust_region == SchurSolverOptions::TrustRegion::kDogleg ? "dogleg" : "LM",
      summary.iterative ? fmt::format("conjugate gradients, {} iterations", summary.cg_iterations)
      : summary.sparse  ? "sparse"
                        : "dense",
      summary.reduced_columns, summary.reduced_fill, summary.message, summary.successful_steps,
      summary.unsuccessful_steps, summary.initial_cost, summary.final_cost, summary.seconds_setup,
      summary.seconds_linearise, summary.seconds_residuals, summary.seconds_solve,
      summary.seconds_factorise, timer.Seconds());
  return rms_from_solver;
}

// Solves `p` with Ceres and the linear solver `solver`.
template <typename ForEachResidual, typename DescribeBlocks>
void SolveWithCeres(const AssembledProblem& p, Solver solver,
                    const ForEachResidual& for_each_residual, const DescribeBlocks& describe_blocks,
                    BundleAdjustmentSummary* result) {
  ceres::Solver::Options solver_options;
  solver_options.minimizer_type = ceres::TRUST_REGION;
  solver_options.trust_region_strategy_type =
      p.options.trust_region == BundleAdjustmentOptions::TrustRegion::kDogleg
          ? ceres::DOGLEG
          : ceres::LEVENBERG_MARQUARDT;
  solver_options.max_num_iterations = p.options.max_iterations;
  solver_options.function_tolerance = p.options.function_tolerance;
  solver_options.gradient_tolerance = p.options.gradient_tolerance;
  solver_options.parameter_tolerance = p.options.parameter_tolerance;
  // Ceres' multi-threaded sums depend on the scheduling: one thread unless asked for more.
  solver_options.num_threads = std::max(1, p.options.num_threads);
  solver_options.minimizer_progress_to_stdout = p.options.verbose;
  solver_options.logging_type = p.options.verbose ? ceres::PER_MINIMIZER_ITERATION : ceres::SILENT;
  result->solver = ConfigureLinearSolver(solver, &solver_options);

  // The problem owns the costs and manifolds, not the loss (`loss` does).
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  for_each_residual([&](const Eigen::Vector2d& xy, ReprojectionBlocks kind,
                        std::optional<unsigned> shared, double* const* blocks, int count) {
    problem.AddResidualBlock(new AnalyticReprojectionCost(xy, kind, shared), p.loss, blocks, count);
  });
  for (ParameterBlockSpec& spec : describe_blocks()) {
    if (spec.constant)
      problem.SetParameterBlockConstant(spec.x);
    else if (spec.manifold)
      problem.SetManifold(spec.x, spec.manifold.release());
  }
  // Schur ordering: points are eliminated first, then cameras and poses. Within a group Ceres
  // orders blocks by address, which the buffer makes the id order.
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  for (const point3D_t id : p.points) ordering->AddElementToGroup(p.buffer.point(id), 0);
  for (const image_t id : p.images)
    if (!p.buffer.HasImageBlock(id)) ordering->AddElementToGroup(p.buffer.pose(id), 1);
  for (const auto& [id, offset] : p.buffer.cameras())
    ordering->AddElementToGroup(p.buffer.camera(id), 1);
  for (double* group : p.used_groups) ordering->AddElementToGroup(group, 1);
  solver_options.linear_solver_ordering = ordering;

  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  if (p.options.verbose) std::printf("%s\n", summary.FullReport().c_str());
  result->success = summary.IsSolutionUsable();
  result->iterations = summary.num_successful_steps + summary.num_unsuccessful_steps;
  result->report = summary.BriefReport();
}

}  // namespace

BundleAdjustmentSummary RunBundleAdjustment(const BundleAdjustmentOptions& options,
                                            const BundleAdjustmentConfig& config,
                                            Reconstruction* reconstruction) {
  const Timer timer;
  Reconstruction& rec = *reconstruction;
  BundleAdjustmentSummary result;
  const std::vector<Observation> observations = CollectObservations(config, rec);
  result.num_residuals = static_cast<int>(observations.size());
  if (observations.empty()) return result;

  std::set<image_t> problem_images;
  std::set<camera_t> problem_cameras;
  std::vector<point3D_t> problem_points;  // ascending: the observations come point by point
  for (const Observation& o : observations) {
    problem_images.insert(o.image_id);
    problem_cameras.insert(rec.image(o.image_id).camera_id);
    if (problem_points.empty() || problem_points.back() != o.point3D_id)
      problem_points.push_back(o.point3D_id);
  }
  const unsigned shared_mask = SharedIntrinsicsMask(options.intrinsics);
  const std::map<camera_t, IntrinsicsGroupKey> group_of_camera =
      SharedGroupMembers(options.intrinsics, config.constant_cameras, problem_images, rec);
  ParameterBuffer buffer(rec, problem_images, group_of_camera, shared_mask, problem_points);

  // The shared per-size blocks the problem's cameras take parameters from.
  std::set<double*> used_groups;
  for (const camera_t id : problem_cameras)
    if (double* group = buffer.group(rec.camera(id))) used_groups.insert(group);

  // The residuals, one per observation, with the blocks they use; `add` receives each.
  const auto for_each_residual = [&](auto&& add) {
    std::array<double*, 4> blocks{};
    for (const Observation& o : observations) {
      const Image& image = rec.image(o.image_id);
      const Camera& camera = rec.camera(image.camera_id);
      double* group = buffer.group(camera);
      const bool image_block = buffer.HasImageBlock(o.image_id);
      int count = 0;
      blocks[count++] = buffer.camera(image.camera_id);
      if (group) blocks[count++] = group;
      if (!image_block) blocks[count++] = buffer.pose(o.image_id);
      blocks[count++] = buffer.point(o.point3D_id);
      add(image.points2D[o.point2D_idx].xy,
          image_block ? ReprojectionBlocks::kImage : ReprojectionBlocks::kCameraPose,
          group ? std::optional<unsigned>(shared_mask) : std::nullopt, blocks.data(), count);
    }
  };

  // Every block the residuals use and how it is held. A camera holds what the options hold and
  // every shared parameter (unused when it is in a group, held when its size formed none, except
  // k1, k2: a photo whose size has too few images for a group still needs its distortion, which
  // its own observations determine as in the per-image policy; held at 0, its focal length
  // absorbs it); a group block holds what the options hold and every parameter that is not
  // shared.
  const auto describe_blocks = [&] {
    std::vector<ParameterBlockSpec> specs;
    const unsigned held_mask = HeldIntrinsicsMask(options.intrinsics);
    constexpr unsigned kDistortion = (1u << Camera::kK1) | (1u << Camera::kK2);
    const auto held_camera = [&](camera_t id) {
      if (config.constant_cameras.count(id)) return kAllCameraParams;
      return held_mask | (group_of_camera.count(id) ? shared_mask : shared_mask & ~kDistortion);
    };
    std::set<camera_t> in_image_blocks;
    const size_t num_constant_points =
        std::count_if(problem_points.begin(), problem_points.end(),
                      [&config](point3D_t id) { return config.constant_points.count(id) > 0; });
    for (const auto& [id, hold_pose] :
         PoseHolds(config, problem_images, num_constant_points, rec)) {
      const camera_t camera_id = rec.image(id).camera_id;
      if (buffer.HasImageBlock(id)) {
        specs.push_back(ImageBlock(hold_pose, held_camera(camera_id), buffer.camera(camera_id)));
        in_image_blocks.insert(camera_id);
      } else {
        specs.push_back(PoseBlock(hold_pose, buffer.pose(id)));
      }
    }
    for (const auto& [id, offset] : buffer.cameras())
      if (!in_image_blocks.count(id))
        specs.push_back(CameraBlock(buffer.camera(id), held_camera(id)));
    for (const auto& [size, offset] : buffer.groups())
      if (double* group = buffer.group(size); used_groups.count(group))
        specs.push_back(CameraBlock(group, held_mask | (kAllCameraParams & ~shared_mask)));
    for (const point3D_t id : problem_points)
      specs.push_back({buffer.point(id), 3, nullptr, config.constant_points.count(id) > 0});
    return specs;
  };

  Solver solver = options.solver;
  if (solver == Solver::kAuto) solver = ChooseSolver(config.variable_pose_images.size());
  if (solver == Solver::kCeresAuto) solver = ChooseCeresSolver(config.variable_pose_images.size());
  const std::unique_ptr<ceres::LossFunction> loss(MakeLoss(options));

  // The native solver reports the RMS from its own residuals (below); for Ceres it is computed
  // here, before the parameters move.
  const double initial_rms =
      solver == Solver::kNativeDenseSchur ? 0.0 : RmsError(rec, observations);
  const AssembledProblem assembled{options,     problem_images,      problem_points,
                                   used_groups, observations.size(), buffer,
                                   loss.get()};
  const bool rms_from_solver =
      solver == Solver::kNativeDenseSchur &&
      SolveNatively(assembled, for_each_residual, describe_blocks, timer, &result);
  if (solver != Solver::kNativeDenseSchur)
    SolveWithCeres(assembled, solver, for_each_residual, describe_blocks, &result);
  if (options.verbose && solver == Solver::kNativeDenseSchur)
    std::printf("%s\n", result.report.c_str());
  buffer.CopyTo(config, &rec);
  if (!rms_from_solver) {
    result.final_rms_px = RmsError(rec, observations);
    // The native solver fails only before its first step: the parameters have not moved.
    result.initial_rms_px = solver == Solver::kNativeDenseSchur ? result.final_rms_px : initial_rms;
  }
  result.seconds = timer.Seconds();
  return result;
}

}  // namespace varsfm
