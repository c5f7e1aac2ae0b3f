#include "varsfm/ba/analytic_reprojection_cost.h"

#include <memory>
#include <optional>
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
      const AnalyticReprojectionCost analytic(in.observed,
                                              ReprojectionBlocks::kCameraRotationTranslation, mask);
      const std::unique_ptr<ceres::CostFunction> autodiff(
          SharedIntrinsicsReprojectionCost::Create(in.observed, mask));
      ExpectSameEvaluation(analytic, *autodiff,
                           {in.camera, in.group, in.rotation, in.translation, in.point});
    }
  }
}

// The pose and image blocks hold [quaternion, centre C] (p = R (X - C)): their residuals and
// Jacobians must be the separate layout's at the point X - C with a zero translation (checked
// against automatic differentiation above), with d/dC = -d/dX; and the residual the separate
// layout gives with t = -R C.
TEST(AnalyticReprojectionCost, PoseAndImageBlocksHoldTheCentre) {
  std::mt19937 rng(5);
  for (const std::optional<unsigned> mask : {std::optional<unsigned>{}, std::optional{0x18u}}) {
    for (int trial = 0; trial < 20; ++trial) {
      const Inputs in = RandomInputs(rng);
      const Eigen::Quaterniond q(in.rotation[3], in.rotation[0], in.rotation[1], in.rotation[2]);
      const Eigen::Vector3d C =
          -(q.conjugate() * Eigen::Map<const Eigen::Vector3d>(in.translation));
      const double zero[3] = {0.0, 0.0, 0.0};
      const double relative[3] = {in.point[0] - C.x(), in.point[1] - C.y(), in.point[2] - C.z()};

      // Reference: separate blocks camera [group] rotation translation point at (0, X - C).
      const AnalyticReprojectionCost separate(in.observed,
                                              ReprojectionBlocks::kCameraRotationTranslation, mask);
      std::vector<const double*> blocks = {in.camera};
      if (mask) blocks.push_back(in.group);
      blocks.insert(blocks.end(), {in.rotation, zero, relative});
      double r_ref[2], J_camera[14], J_group[14], J_rotation[8], J_translation[6], J_point[6];
      std::vector<double*> jac = {J_camera};
      if (mask) jac.push_back(J_group);
      jac.insert(jac.end(), {J_rotation, J_translation, J_point});
      ASSERT_TRUE(separate.Evaluate(blocks.data(), r_ref, jac.data()));
      // The same residual as with the translation.
      std::vector<const double*> with_t = {in.camera};
      if (mask) with_t.push_back(in.group);
      with_t.insert(with_t.end(), {in.rotation, in.translation, in.point});
      double r_t[2];
      ASSERT_TRUE(separate.Evaluate(with_t.data(), r_t, nullptr));
      EXPECT_NEAR(r_ref[0], r_t[0], 1e-9);
      EXPECT_NEAR(r_ref[1], r_t[1], 1e-9);

      double pose[7], image[14];
      std::copy_n(in.rotation, 4, pose);
      std::copy_n(C.data(), 3, pose + 4);
      std::copy_n(in.camera, 7, image);
      std::copy_n(pose, 7, image + 7);
      for (const ReprojectionBlocks layout :
           {ReprojectionBlocks::kCameraPose, ReprojectionBlocks::kImage}) {
        const AnalyticReprojectionCost cost(in.observed, layout, mask);
        const bool image_block = layout == ReprojectionBlocks::kImage;
        std::vector<const double*> b = {image_block ? image : in.camera};
        if (mask) b.push_back(in.group);
        if (!image_block) b.push_back(pose);
        b.push_back(in.point);
        double r[2], J_own[28], J_g[14], J_pose[14], J_p[6];
        std::vector<double*> j = {J_own};
        if (mask) j.push_back(J_g);
        if (!image_block) j.push_back(J_pose);
        j.push_back(J_p);
        ASSERT_EQ(cost.parameter_block_sizes().size(), b.size());
        ASSERT_TRUE(cost.Evaluate(b.data(), r, j.data()));
        EXPECT_EQ(r[0], r_ref[0]);
        EXPECT_EQ(r[1], r_ref[1]);
        // Row `row`, parameter `k` of the pose part (rotation 0-3, centre 4-6).
        const auto pose_jacobian = [&](int row, int k) {
          return image_block ? J_own[row * 14 + 7 + k] : J_pose[row * 7 + k];
        };
        const int own_stride = image_block ? 14 : 7;
        for (int row = 0; row < 2; ++row) {
          for (int k = 0; k < 7; ++k) EXPECT_EQ(J_own[row * own_stride + k], J_camera[row * 7 + k]);
          if (mask)
            for (int k = 0; k < 7; ++k) EXPECT_EQ(J_g[row * 7 + k], J_group[row * 7 + k]);
          for (int k = 0; k < 4; ++k) EXPECT_EQ(pose_jacobian(row, k), J_rotation[row * 4 + k]);
          for (int k = 0; k < 3; ++k) EXPECT_EQ(pose_jacobian(row, 4 + k), -J_point[row * 3 + k]);
          for (int k = 0; k < 3; ++k) EXPECT_EQ(J_p[row * 3 + k], J_point[row * 3 + k]);
        }
      }
    }
  }
}

}  // namespace
}  // namespace varsfm
