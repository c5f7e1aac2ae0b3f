#include "varsfm/ba/dense_schur_solver.h"

#include <cmath>
#include <random>
#include <vector>

#include <ceres/ceres.h>
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

TEST(DenseSchurSolver, FitsACurveAsCeresDoes) {
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
      DenseSchurOptions options;
      options.function_tolerance = 1e-12;
      const DenseSchurSummary s = SolveWithDenseSchur(options, {}, &problem);
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

TEST(DenseSchurSolver, EliminatesPointsOnAManifoldWithARobustLoss) {
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
  DenseSchurOptions options;
  options.function_tolerance = 1e-14;
  options.gradient_tolerance = 1e-14;
  const DenseSchurSummary s = SolveWithDenseSchur(options, points, &native.problem);
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

TEST(DenseSchurSolver, StopsAtTheIterationLimitWithAUsableSolution) {
  double mc[2] = {0.0, 0.0};
  ceres::Problem problem;
  for (int i = 0; i < 20; ++i) {
    const double x = 0.25 * i;
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<ExponentialResidual, 1, 1, 1>(
                                 new ExponentialResidual(x, std::exp(0.3 * x + 0.1))),
                             nullptr, &mc[0], &mc[1]);
  }
  DenseSchurOptions options;
  options.max_iterations = 2;
  const DenseSchurSummary s = SolveWithDenseSchur(options, {}, &problem);
  EXPECT_TRUE(s.usable);
  EXPECT_FALSE(s.converged);
  EXPECT_EQ(s.successful_steps + s.unsuccessful_steps, 2);
  EXPECT_LE(s.final_cost, s.initial_cost);
}

}  // namespace
}  // namespace varsfm
