#include "varsfm/ba/schur_solver.h"

#include <array>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>

namespace varsfm {
namespace {

// y = exp(m x + c): Ceres' curve-fitting example, no block to eliminate (the reduced system is
// the whole problem) and one residual per block pair.
struct ExponentialResidual {
  ExponentialResidual(double x, double y) : x(x), y(y) {}
  template <typename T>
  bool operator()(const T* m, const T* c, T* residual) const {
    residual[0] = y - exp(m[0] * x + c[0]);
    return true;
  }
  double x, y;
};

// Three residuals (not the two of a reprojection) between a shared rotation (a quaternion on
// its manifold) and a point that is eliminated: R X - observed, and a prior X - z on the point.
struct RotatedPointResidual {
  explicit RotatedPointResidual(const Eigen::Vector3d& observed) : observed(observed) {}
  template <typename T>
  bool operator()(const T* q, const T* x, T* residual) const {
    const Eigen::Quaternion<T> rotation(q[3], q[0], q[1], q[2]);
    const Eigen::Matrix<T, 3, 1> p = rotation * Eigen::Map<const Eigen::Matrix<T, 3, 1>>(x);
    for (int i = 0; i < 3; ++i) residual[i] = p[i] - T(observed[i]);
    return true;
  }
  Eigen::Vector3d observed;
};

struct PointPrior {
  explicit PointPrior(const Eigen::Vector3d& z) : z(z) {}
  template <typename T>
  bool operator()(const T* x, T* residual) const {
    for (int i = 0; i < 3; ++i) residual[i] = x[i] - T(z[i]);
    return true;
  }
  Eigen::Vector3d z;
};

// A pinhole camera [angle-axis (3), translation (3), focal length (1)] observing a point.
struct PinholeResidual {
  explicit PinholeResidual(const Eigen::Vector2d& observed) : observed(observed) {}
  template <typename T>
  bool operator()(const T* camera, const T* x, T* residual) const {
    T p[3];
    ceres::AngleAxisRotatePoint(camera, x, p);
    for (int i = 0; i < 3; ++i) p[i] += camera[3 + i];
    residual[0] = camera[6] * p[0] / p[2] - T(observed.x());
    residual[1] = camera[6] * p[1] / p[2] - T(observed.y());
    return true;
  }
  Eigen::Vector2d observed;
};

// A street: 80 cameras one unit apart along x looking at points 4-6 units away, each point seen
// by ~6 neighbouring cameras, so the reduced system (560 columns) is banded. Perturbed start,
// 0.5 px noise, the first two cameras held (the gauge).
struct StreetProblem {
  std::vector<std::array<double, 7>> cameras;
  std::vector<Eigen::Vector3d> points;
  ceres::Problem problem;

  StreetProblem() {
    std::mt19937 rng(11);
    std::normal_distribution<double> n(0.0, 1.0);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    constexpr int kCameras = 80;
    for (int i = 0; i < kCameras; ++i) cameras.push_back({0, 0, 0, -1.0 * i, 0, 0, 500.0});
    std::vector<std::vector<std::pair<int, Eigen::Vector2d>>> seen;
    for (int k = 0; k < 2400; ++k) {
      const Eigen::Vector3d x(-2.0 + (kCameras + 3.0) * u(rng), -1.0 + 2.0 * u(rng),
                              4.0 + 2.0 * u(rng));
      std::vector<std::pair<int, Eigen::Vector2d>> obs;
      for (int i = 0; i < kCameras; ++i) {
        const Eigen::Vector2d pixel(500.0 * (x.x() - i) / x.z(), 500.0 * x.y() / x.z());
        if (std::abs(pixel.x()) < 320.0)
          obs.emplace_back(i, pixel + 0.5 * Eigen::Vector2d(n(rng), n(rng)));
      }
      if (obs.size() < 2) continue;
      points.push_back(x + 0.02 * Eigen::Vector3d(n(rng), n(rng), n(rng)));
      seen.push_back(std::move(obs));
    }
    for (size_t i = 2; i < cameras.size(); ++i) {
      for (int j = 3; j < 6; ++j) cameras[i][j] += 0.02 * n(rng);
      cameras[i][6] *= 1.0 + 0.02 * n(rng);
    }
    for (size_t k = 0; k < points.size(); ++k)
      for (const auto& [i, pixel] : seen[k])
        problem.AddResidualBlock(
            new ceres::AutoDiffCostFunction<PinholeResidual, 2, 7, 3>(new PinholeResidual(pixel)),
            new ceres::CauchyLoss(1.0), cameras[i].data(), points[k].data());
    problem.SetParameterBlockConstant(cameras[0].data());
    problem.SetParameterBlockConstant(cameras[1].data());
  }
  std::vector<double*> PointBlocks() {
    std::vector<double*> blocks;
    for (Eigen::Vector3d& x : points) blocks.push_back(x.data());
    return blocks;
  }
};

// The sparse factorisation of a banded reduced system gives the dense one's steps: the same
// iterations and minimum. kAuto picks it for this problem.
TEST(SchurSolver, SparseFactorisationEqualsDense) {
  StreetProblem dense_problem, sparse_problem, auto_problem;
  SchurSolverOptions options;
  options.function_tolerance = 1e-10;
  options.factorization = SchurSolverOptions::Factorization::kDense;
  const SchurSolverSummary dense =
      SolveWithSchurComplement(options, dense_problem.PointBlocks(), &dense_problem.problem);
  options.factorization = SchurSolverOptions::Factorization::kSparse;
  const SchurSolverSummary sparse =
      SolveWithSchurComplement(options, sparse_problem.PointBlocks(), &sparse_problem.problem);
  options.factorization = SchurSolverOptions::Factorization::kAuto;
  const SchurSolverSummary automatic =
      SolveWithSchurComplement(options, auto_problem.PointBlocks(), &auto_problem.problem);
  ASSERT_TRUE(dense.usable && sparse.usable) << dense.message << " / " << sparse.message;
  EXPECT_FALSE(dense.sparse);
  EXPECT_TRUE(sparse.sparse);
  EXPECT_TRUE(automatic.sparse);
  EXPECT_LT(sparse.final_cost, 0.5 * sparse.initial_cost);
  EXPECT_EQ(sparse.successful_steps, dense.successful_steps);
  EXPECT_NEAR(sparse.final_cost, dense.final_cost, 1e-9 * dense.final_cost);
  for (size_t i = 0; i < dense_problem.cameras.size(); ++i)
    for (int j = 0; j < 7; ++j)
      EXPECT_NEAR(sparse_problem.cameras[i][j], dense_problem.cameras[i][j], 1e-6) << i << " " << j;
}

// Conjugate gradients on the reduced system (reduced_camera_pcg.cc) reach the minimum of the
// direct (sparse Cholesky) solve, with Levenberg-Marquardt and with the dogleg (whose model
// then carries the solve's residual), and give the same result bit for bit with any number of
// threads.
TEST(SchurSolver, ConjugateGradientsReachTheDirectMinimum) {
  for (const auto region : {SchurSolverOptions::TrustRegion::kLevenbergMarquardt,
                            SchurSolverOptions::TrustRegion::kDogleg}) {
    SCOPED_TRACE(static_cast<int>(region));
    StreetProblem direct_problem, cg_problem, cg_threads_problem;
    SchurSolverOptions options;
    options.trust_region = region;
    options.function_tolerance = 1e-10;
    options.factorization = SchurSolverOptions::Factorization::kSparse;
    const SchurSolverSummary direct =
        SolveWithSchurComplement(options, direct_problem.PointBlocks(), &direct_problem.problem);
    options.iterative_min_blocks = 1;
    const SchurSolverSummary cg =
        SolveWithSchurComplement(options, cg_problem.PointBlocks(), &cg_problem.problem);
    options.num_threads = 2;
    const SchurSolverSummary cg_threads = SolveWithSchurComplement(
        options, cg_threads_problem.PointBlocks(), &cg_threads_problem.problem);
    ASSERT_TRUE(direct.usable && cg.usable) << direct.message << " / " << cg.message;
    EXPECT_FALSE(direct.iterative);
    EXPECT_TRUE(cg.iterative);
    EXPECT_GT(cg.cg_iterations, 0);
    EXPECT_LT(cg.final_cost, 0.5 * cg.initial_cost);
    EXPECT_NEAR(cg.final_cost, direct.final_cost, 1e-8 * direct.final_cost);
    // Both stop at the function tolerance on a flat minimum (the street's bend): poses agree to
    // 1e-4 (perturbed by 0.02), focal lengths to 1e-6 relative (perturbed by 2 %).
    for (size_t i = 0; i < direct_problem.cameras.size(); ++i)
      for (int j = 0; j < 7; ++j)
        EXPECT_NEAR(cg_problem.cameras[i][j], direct_problem.cameras[i][j],
                    j < 6 ? 1e-4 : 1e-6 * direct_problem.cameras[i][j])
            << i << " " << j;
    EXPECT_EQ(cg_threads.final_cost, cg.final_cost);
    EXPECT_EQ(cg_threads_problem.cameras, cg_problem.cameras);
  }
}

// The work is cut into fixed parts summed in a fixed order: any number of threads gives the
// same iterations and the same minimum, bit for bit.
TEST(SchurSolver, SameResultBitForBitWithAnyNumberOfThreads) {
  StreetProblem reference;
  SchurSolverOptions options;
  const SchurSolverSummary one =
      SolveWithSchurComplement(options, reference.PointBlocks(), &reference.problem);
  ASSERT_TRUE(one.usable) << one.message;
  for (const int threads : {2, 3, 16}) {
    SCOPED_TRACE(threads);
    StreetProblem street;
    options.num_threads = threads;
    const SchurSolverSummary summary =
        SolveWithSchurComplement(options, street.PointBlocks(), &street.problem);
    EXPECT_EQ(summary.successful_steps, one.successful_steps);
    EXPECT_EQ(summary.final_cost, one.final_cost);
    EXPECT_EQ(street.cameras, reference.cameras);
    for (size_t k = 0; k < street.points.size(); ++k)
      EXPECT_EQ(street.points[k], reference.points[k]) << k;
  }
}

// Powell's dogleg reaches the minimum Levenberg-Marquardt and Ceres' DOGLEG reach, on the
// banded street (sparse reduced system) with a robust loss.
TEST(SchurSolver, DoglegReachesTheMinimumAsLevenbergMarquardtAndCeresDogleg) {
  StreetProblem lm, dogleg, reference;
  SchurSolverOptions options;
  options.function_tolerance = 1e-12;
  options.gradient_tolerance = 1e-12;
  const SchurSolverSummary lm_summary =
      SolveWithSchurComplement(options, lm.PointBlocks(), &lm.problem);
  options.trust_region = SchurSolverOptions::TrustRegion::kDogleg;
  const SchurSolverSummary dl_summary =
      SolveWithSchurComplement(options, dogleg.PointBlocks(), &dogleg.problem);
  ASSERT_TRUE(lm_summary.usable && dl_summary.usable)
      << lm_summary.message << " / " << dl_summary.message;
  EXPECT_TRUE(dl_summary.converged) << dl_summary.message;
  EXPECT_LT(dl_summary.final_cost, 0.5 * dl_summary.initial_cost);

  ceres::Solver::Options ceres_options;
  ceres_options.trust_region_strategy_type = ceres::DOGLEG;
  ceres_options.linear_solver_type = ceres::SPARSE_SCHUR;
  ceres_options.function_tolerance = 1e-12;
  ceres_options.gradient_tolerance = 1e-12;
  ceres::Solver::Summary summary;
  ceres::Solve(ceres_options, &reference.problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.BriefReport();

  // The same minimum: LM and Ceres' dogleg stop where a step gains less than 1e-12 of the cost
  // while the street's weak directions (its bend) still give way (their costs ~1.5e-8 above the
  // native dogleg's, whose extrapolated steps follow those directions further); no lower.
  EXPECT_LE(dl_summary.final_cost, lm_summary.final_cost * (1.0 + 1e-12));
  EXPECT_LE(dl_summary.final_cost, summary.final_cost * (1.0 + 1e-12));
  EXPECT_NEAR(dl_summary.final_cost, lm_summary.final_cost, 1e-7 * lm_summary.final_cost);
  EXPECT_NEAR(dl_summary.final_cost, summary.final_cost, 1e-7 * summary.final_cost);
  for (size_t i = 0; i < lm.cameras.size(); ++i)
    for (int j = 0; j < 7; ++j) {
      EXPECT_NEAR(dogleg.cameras[i][j], lm.cameras[i][j], 1e-4) << i << " " << j;
      EXPECT_NEAR(dogleg.cameras[i][j], reference.cameras[i][j], 1e-4) << i << " " << j;
    }
}

TEST(SchurSolver, FitsACurveAsCeresDoes) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.2);
  std::vector<std::pair<double, double>> data;
  for (int i = 0; i < 60; ++i) {
    const double x = 5.0 * i / 60.0;
    data.emplace_back(x, std::exp(0.3 * x + 0.1) + noise(rng));
  }
  double native[2] = {0.0, 0.0}, reference[2] = {0.0, 0.0};
  for (double* mc : {native, reference}) {
    ceres::Problem problem;
    for (const auto& [x, y] : data)
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<ExponentialResidual, 1, 1, 1>(
                                   new ExponentialResidual(x, y)),
                               nullptr, &mc[0], &mc[1]);
    if (mc == native) {
      SchurSolverOptions options;
      options.function_tolerance = 1e-12;
      const SchurSolverSummary s = SolveWithSchurComplement(options, {}, &problem);
      EXPECT_TRUE(s.usable && s.converged) << s.message;
      EXPECT_LT(s.final_cost, s.initial_cost);
    } else {
      ceres::Solver::Options options;
      options.function_tolerance = 1e-12;
      ceres::Solver::Summary summary;
      ceres::Solve(options, &problem, &summary);
    }
  }
  EXPECT_NEAR(native[0], reference[0], 1e-7);
  EXPECT_NEAR(native[1], reference[1], 1e-7);
  EXPECT_NEAR(native[0], 0.3, 0.02);
}

TEST(SchurSolver, EliminatesPointsOnAManifoldWithARobustLoss) {
  std::mt19937 rng(5);
  std::normal_distribution<double> n(0.0, 1.0);
  const Eigen::Quaterniond truth(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  std::vector<Eigen::Vector3d> observed, prior;
  for (int i = 0; i < 40; ++i) {
    const Eigen::Vector3d x(n(rng), n(rng), n(rng));
    observed.push_back(truth * x + 0.01 * Eigen::Vector3d(n(rng), n(rng), n(rng)));
    prior.push_back(x + 0.01 * Eigen::Vector3d(n(rng), n(rng), n(rng)));
  }
  observed[3] += Eigen::Vector3d(2.0, -1.0, 0.5);  // an outlier for the loss
  struct Solution {
    Eigen::Vector4d q = Eigen::Quaterniond::Identity().coeffs();
    std::vector<Eigen::Vector3d> x;
    ceres::Problem problem;
  };
  Solution native, reference;
  for (Solution* s : {&native, &reference}) {
    s->x.assign(prior.begin(), prior.end());
    for (size_t i = 0; i < prior.size(); ++i) {
      s->problem.AddResidualBlock(new ceres::AutoDiffCostFunction<RotatedPointResidual, 3, 4, 3>(
                                      new RotatedPointResidual(observed[i])),
                                  new ceres::HuberLoss(0.05), s->q.data(), s->x[i].data());
      s->problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<PointPrior, 3, 3>(new PointPrior(prior[i])), nullptr,
          s->x[i].data());
    }
    s->problem.SetManifold(s->q.data(), new ceres::EigenQuaternionManifold);
  }
  std::vector<double*> points;
  for (Eigen::Vector3d& x : native.x) points.push_back(x.data());
  SchurSolverOptions options;
  options.function_tolerance = 1e-14;
  options.gradient_tolerance = 1e-14;
  const SchurSolverSummary s = SolveWithSchurComplement(options, points, &native.problem);
  ASSERT_TRUE(s.usable) << s.message;
  ceres::Solver::Options ceres_options;
  ceres_options.function_tolerance = 1e-14;
  ceres_options.gradient_tolerance = 1e-14;
  ceres::Solver::Summary summary;
  ceres::Solve(ceres_options, &reference.problem, &summary);
  EXPECT_NEAR(s.final_cost, summary.final_cost, 1e-9 * summary.final_cost);
  EXPECT_LT((native.q - reference.q).norm(), 1e-7);
  for (size_t i = 0; i < points.size(); ++i)
    EXPECT_LT((native.x[i] - reference.x[i]).norm(), 1e-7) << i;
  EXPECT_LT(Eigen::Quaterniond(native.q).angularDistance(truth), 0.01);
}

TEST(SchurSolver, StopsAtTheIterationLimitWithAUsableSolution) {
  double mc[2] = {0.0, 0.0};
  ceres::Problem problem;
  for (int i = 0; i < 20; ++i) {
    const double x = 0.25 * i;
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<ExponentialResidual, 1, 1, 1>(
                                 new ExponentialResidual(x, std::exp(0.3 * x + 0.1))),
                             nullptr, &mc[0], &mc[1]);
  }
  SchurSolverOptions options;
  options.max_iterations = 2;
  const SchurSolverSummary s = SolveWithSchurComplement(options, {}, &problem);
  EXPECT_TRUE(s.usable);
  EXPECT_FALSE(s.converged);
  EXPECT_EQ(s.successful_steps + s.unsuccessful_steps, 2);
  EXPECT_LE(s.final_cost, s.initial_cost);
}

// The mapper hands the solver its blocks directly (LeastSquaresProblem); the same blocks through a
// ceres::Problem must give the same steps and minimum, bit for bit.
TEST(SchurSolver, LeastSquaresProblemSolvesAsTheCeresProblemWithTheSameBlocks) {
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 0.2);
  std::vector<std::unique_ptr<ceres::CostFunction>> costs;
  std::vector<std::pair<double, double>> data;
  for (int i = 0; i < 40; ++i) {
    const double x = 4.0 * i / 40.0;
    data.emplace_back(x, std::exp(0.3 * x + 0.1) + noise(rng));
  }
  double direct[2] = {0.0, 0.0}, through_ceres[2] = {0.0, 0.0};
  ceres::CauchyLoss loss(1.0);
  LeastSquaresProblem problem;
  problem.AddParameterBlock(&direct[0], 1);
  problem.AddParameterBlock(&direct[1], 1);
  ceres::Problem::Options ceres_options;
  ceres_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem reference(ceres_options);
  for (const auto& [x, y] : data) {
    costs.push_back(std::make_unique<ceres::AutoDiffCostFunction<ExponentialResidual, 1, 1, 1>>(
        new ExponentialResidual(x, y)));
    const double* blocks[2] = {&direct[0], &direct[1]};
    problem.AddResidualBlock(costs.back().get(), &loss, blocks, 2);
    reference.AddResidualBlock(costs.back().get(), &loss, &through_ceres[0], &through_ceres[1]);
  }
  const SchurSolverOptions options;
  const SchurSolverSummary a = SolveWithSchurComplement(options, {}, problem);
  const SchurSolverSummary b = SolveWithSchurComplement(options, {}, &reference);
  ASSERT_TRUE(a.usable && a.converged) << a.message;
  EXPECT_EQ(a.successful_steps, b.successful_steps);
  EXPECT_EQ(a.final_cost, b.final_cost);
  EXPECT_EQ(direct[0], through_ceres[0]);
  EXPECT_EQ(direct[1], through_ceres[1]);
  EXPECT_NEAR(direct[0], 0.3, 0.05);
}

TEST(SchurSolver, RefusesAResidualOnABlockTheProblemDoesNotHave) {
  double m = 0.0, c = 0.0;
  ceres::AutoDiffCostFunction<ExponentialResidual, 1, 1, 1> cost(new ExponentialResidual(1, 2));
  LeastSquaresProblem problem;
  problem.AddParameterBlock(&m, 1);  // c is never added
  const double* blocks[2] = {&m, &c};
  problem.AddResidualBlock(&cost, nullptr, blocks, 2);
  const SchurSolverSummary s = SolveWithSchurComplement(SchurSolverOptions(), {}, problem);
  EXPECT_FALSE(s.usable);
  EXPECT_NE(s.message.find("does not have"), std::string::npos) << s.message;
  EXPECT_EQ(m, 0.0);
  EXPECT_EQ(c, 0.0);
}

}  // namespace
}  // namespace varsfm
