// Global bundle adjustment from a perturbed start, 0.5 px noise, per-image intrinsics (f, k1,
// k2 free):
//  - BM_GlobalBundleAdjustment: 30 images and 15,000 points, for each linear solver choice
//    (ba/bundle_adjuster.cc, ChooseSolver) and thread count;
//  - BM_SmallBundleAdjustment: 10 images and 1,000 points with the mapper's shared principal
//    point, the size of a small photo set's final adjustment, for the project's Schur solver
//    (schur_solver.h, LM) against Ceres' DENSE_SCHUR.
// Reports time, iterations and the final RMS.
#include <benchmark/benchmark.h>

#include <random>

#include "varsfm/ba/bundle_adjuster.h"
#include "varsfm/synthetic/synthetic_reconstruction.h"

namespace varsfm {
namespace {

// The scene as a reconstruction with poses, points and focals moved off the truth.
Reconstruction PerturbedScene(int num_images, int num_points) {
  SyntheticOptions o;
  o.num_images = num_images;
  o.num_points = num_points;
  o.arc_degrees = 90.0;
  o.focal_start = 800.0;
  o.focal_end = 1280.0;
  o.noise_sigma = 0.5;
  Reconstruction rec = ReconstructionFromSynthetic(GenerateSyntheticScene(o));
  Rng rng(1);
  std::normal_distribution<double> n(0.0, 1.0);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  for (const image_t id : rec.RegisteredImageIds()) {
    Rigid3d& pose = rec.image(id).cam_from_world;
    const Eigen::Vector3d axis(n(rng), n(rng), n(rng));
    pose.rotation = Eigen::AngleAxisd(0.5 * M_PI / 180.0, axis.normalized()) * pose.rotation;
    pose.translation += 0.1 * Eigen::Vector3d(n(rng), n(rng), n(rng));
    rec.CameraOf(id).focal() *= 1.0 + u(rng);
  }
  for (auto& [id, point] : rec.points3D())
    point.xyz += 0.02 * Eigen::Vector3d(n(rng), n(rng), n(rng));
  return rec;
}

// Times the global adjustment of a copy of `start` and reports the solver, iterations and RMS.
void AdjustAndReport(const Reconstruction& start, const BundleAdjustmentOptions& options,
                     benchmark::State& state) {
  BundleAdjustmentSummary summary;
  for (auto _ : state) {
    state.PauseTiming();
    Reconstruction rec = start;
    state.ResumeTiming();
    summary = RunBundleAdjustment(options, BundleAdjustmentConfig::Global(rec), &rec);
  }
  state.SetLabel(summary.solver);
  state.counters["iterations"] = summary.iterations;
  state.counters["final_rms_px"] = summary.final_rms_px;
  state.counters["observations"] = summary.num_residuals;
}

void BM_GlobalBundleAdjustment(benchmark::State& state) {
  static const Reconstruction start = PerturbedScene(30, 15000);
  BundleAdjustmentOptions options;
  options.solver = static_cast<BundleAdjustmentOptions::Solver>(state.range(0));
  options.num_threads = static_cast<int>(state.range(1));
  AdjustAndReport(start, options, state);
}
// Ceres' solvers kDenseSchur, kSparseSchurSuiteSparse, kSparseSchurEigen, kIterativeSchur
// (1..4; 0 is kAuto, which picks the native solver, 5), each with 1 thread (the reproducible
// default) and 2.
BENCHMARK(BM_GlobalBundleAdjustment)
    ->ArgsProduct({{1, 2, 3, 4}, {1, 2}})
    ->ArgNames({"solver", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->UseRealTime();

void BM_SmallBundleAdjustment(benchmark::State& state) {
  static const Reconstruction start = PerturbedScene(10, 1000);
  BundleAdjustmentOptions options;
  options.solver = static_cast<BundleAdjustmentOptions::Solver>(state.range(0));
  options.function_tolerance = 1e-5;  // the mapper's global adjustments
  options.intrinsics.refine_principal_point = true;
  options.intrinsics.shared_per_size = {Camera::kU0, Camera::kV0};
  AdjustAndReport(start, options, state);
}
// kNativeDenseSchur (5) and kDenseSchur (1), one thread.
BENCHMARK(BM_SmallBundleAdjustment)
    ->Arg(5)
    ->Arg(1)
    ->ArgName("solver")
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(5)
    ->UseRealTime();

}  // namespace
}  // namespace varsfm
