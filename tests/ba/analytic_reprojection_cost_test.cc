#include "varsfm/ba/analytic_reprojection_cost.h"

#include <memory>
#include <random>

#include <gtest/gtest.h>

#include "varsfm/ba/reprojection_cost.h"

namespace varsfm {
namespace {

// Random but valid inputs: a unit quaternion, a point in front of the camera, intrinsics with
// aspect, skew, an off-centre principal point and distortion.
struct Inputs {
  double camera[Camera::kNumParams];
  double group[Camera::kNumParams];
  double rotation[4];
  double translation[3];
  double point[3];
  Eigen::Vector2d observed;
};

Inputs RandomInputs(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Inputs in;
  const double camera[] = {900 + 200 * u(rng), 1.0 + 0.05 * u(rng), 2 * u(rng),   512 + 20 * u(rng),
                           340 + 20 * u(rng),  0.2 * u(rng),        0.05 * u(rng)};
  std::copy(camera, camera + Camera::kNumParams, in.camera);
  for (int i = 0; i < Camera::kNumParams; ++i) in.group[i] = camera[i] * (1.0 + 0.1 * u(rng));
  Eigen::Quaterniond q(u(rng), u(rng), u(rng), u(rng));
  q.normalize();
  std::copy(q.coeffs().data(), q.coeffs().data() + 4, in.rotation);
  const Eigen::Vector3d t(u(rng), u(rng), 5.0 + u(rng));
  std::copy(t.data(), t.data() + 3, in.translation);
  // A point whose camera coordinates lie in front, within the field of view.
  const Eigen::Vector3d p_cam(u(rng), 0.7 * u(rng), 4.0 + u(rng));
  const Eigen::Vector3d X = q.conjugate() * (p_cam - t);
  std::copy(X.data(), X.data() + 3, in.point);
  in.observed = Eigen::Vector2d(500 + 100 * u(rng), 300 + 100 * u(rng));
  return in;
}

// Residuals and every block's Jacobian of `cost`, blocks of the given sizes.
void ExpectSameEvaluation(const ceres::CostFunction& analytic, const ceres::CostFunction& autodiff,
                          const std::vector<const double*>& blocks) {
  const auto& sizes = analytic.parameter_block_sizes();
  ASSERT_EQ(sizes, autodiff.parameter_block_sizes());
  std::vector<std::vector<double>> ja(sizes.size()), jb(sizes.size());
  std::vector<double*> pa, pb;
  for (size_t i = 0; i < sizes.size(); ++i) {
    ja[i].assign(2 * sizes[i], 0.0);
    jb[i].assign(2 * sizes[i], 0.0);
    pa.push_back(ja[i].data());
    pb.push_back(jb[i].data());
  }
  double ra[2], rb[2];
  ASSERT_TRUE(analytic.Evaluate(blocks.data(), ra, pa.data()));
  ASSERT_TRUE(autodiff.Evaluate(blocks.data(), rb, pb.data()));
  EXPECT_NEAR(ra[0], rb[0], 1e-9);
  EXPECT_NEAR(ra[1], rb[1], 1e-9);
  for (size_t i = 0; i < sizes.size(); ++i)
    for (size_t k = 0; k < ja[i].size(); ++k)
      EXPECT_NEAR(ja[i][k], jb[i][k], 1e-9 * (1.0 + std::abs(jb[i][k])))
          << "block " << i << " entry " << k;
  // Residual-only evaluation (no Jacobians requested) gives the same residuals.
  double rc[2];
  ASSERT_TRUE(analytic.Evaluate(blocks.data(), rc, nullptr));
  EXPECT_EQ(rc[0], ra[0]);
  EXPECT_EQ(rc[1], ra[1]);
}

TEST(AnalyticReprojectionCost, MatchesAutomaticDifferentiation) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 50; ++trial) {
    const Inputs in = RandomInputs(rng);
    const AnalyticReprojectionCost analytic(in.observed);
    const std::unique_ptr<ceres::CostFunction> autodiff(ReprojectionCost::Create(in.observed));
    ExpectSameEvaluation(analytic, *autodiff, {in.camera, in.rotation, in.translation, in.point});
  }
}

TEST(AnalyticReprojectionCost, SharedIntrinsicsMatchAutomaticDifferentiation) {
  std::mt19937 rng(4);
  for (const unsigned mask : {0u, 0x18u, 0x7eu, 0x7fu}) {  // none, (u0, v0), all but f, all
    for (int trial = 0; trial < 20; ++trial) {
      const Inputs in = RandomInputs(rng);
      const AnalyticSharedIntrinsicsReprojectionCost analytic(in.observed, mask);
      const std::unique_ptr<ceres::CostFunction> autodiff(
          SharedIntrinsicsReprojectionCost::Create(in.observed, mask));
      ExpectSameEvaluation(analytic, *autodiff,
                           {in.camera, in.group, in.rotation, in.translation, in.point});
    }
  }
}

}  // namespace
}  // namespace varsfm
