#include "varsfm/matching/geometric_verification.h"

#include <random>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "varsfm/util/option_check.h"

namespace varsfm {
namespace {

// Two views of a synthetic scene: `num_inliers` true correspondences (0.3 px noise) followed
// by `num_outliers` random ones, matched index to index.
struct SyntheticPair {
  FeatureKeypoints keypoints1, keypoints2;
  FeatureMatches matches;
  Matrix3d R = Matrix3d::Identity();  // camera 2 from camera 1
  Vector3d t = Vector3d::Zero();
  Matrix3d K;
};

SyntheticPair MakePair(int num_inliers, int num_outliers, bool planar, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.3);
  SyntheticPair pair;
  pair.K << 800, 0, 512, 0, 800, 384, 0, 0, 1;
  pair.R = Eigen::AngleAxisd(0.15, Vector3d(0.2, 1.0, 0.1).normalized()).toRotationMatrix();
  pair.t = Vector3d(-1.0, 0.1, 0.2);
  auto project = [&](const Vector3d& x) {
    const Vector3d p = pair.K * x;
    return Vector2d(p.x() / p.z(), p.y() / p.z());
  };
  while (static_cast<int>(pair.matches.size()) < num_inliers) {
    // A box of depth 4..8 in front of camera 1, or the slanted plane z = 6 + 0.3 x.
    Vector3d x(2.5 * u(rng), 2.0 * u(rng), 6.0 + 2.0 * u(rng));
    if (planar) x.z() = 6.0 + 0.3 * x.x();
    const Vector2d p1 = project(x), p2 = project(pair.R * x + pair.t);
    if (p1.minCoeff() < 0 || p2.minCoeff() < 0 || p1.x() > 1024 || p2.x() > 1024 || p1.y() > 768 ||
        p2.y() > 768) {
      continue;
    }
    const point2D_t idx = pair.keypoints1.size();
    pair.keypoints1.emplace_back(p1.x() + noise(rng), p1.y() + noise(rng));
    pair.keypoints2.emplace_back(p2.x() + noise(rng), p2.y() + noise(rng));
    pair.matches.push_back({idx, idx});
  }
  std::uniform_real_distribution<double> ux(0, 1024), uy(0, 768);
  for (int k = 0; k < num_outliers; ++k) {
    const point2D_t idx = pair.keypoints1.size();
    pair.keypoints1.emplace_back(ux(rng), uy(rng));
    pair.keypoints2.emplace_back(ux(rng), uy(rng));
    pair.matches.push_back({idx, idx});
  }
  return pair;
}

int CountTrueInliers(const TwoViewGeometry& geometry, int num_inliers) {
  int n = 0;
  for (const FeatureMatch& m : geometry.inlier_matches)
    n += m.point2D_idx1 < point2D_t(num_inliers);
  return n;
}

class VerificationMethods : public ::testing::TestWithParam<RansacMethod> {};

TEST_P(VerificationMethods, FindsInliersAmongHalfOutliers) {
  const SyntheticPair pair = MakePair(200, 200, false, 7);
  VerificationOptions options;
  options.method = GetParam();
  const TwoViewGeometry g =
      VerifyTwoViewGeometry(pair.keypoints1, pair.keypoints2, pair.matches, options);
  EXPECT_EQ(g.config, TwoViewGeometry::kUncalibrated);
  const int true_inliers = CountTrueInliers(g, 200);
  EXPECT_GE(true_inliers, 185);  // 0.3 px noise vs a 1.5 px threshold
  // A random outlier lies within 1.5 px of its epipolar line with probability ~0.3 %.
  EXPECT_LE(static_cast<int>(g.inlier_matches.size()) - true_inliers, 5);

  // F in varsfm pixel coordinates: the true F = K^-T [t]x R K^-1 agrees up to scale.
  Matrix3d tx;
  tx << 0, -pair.t.z(), pair.t.y(), pair.t.z(), 0, -pair.t.x(), -pair.t.y(), pair.t.x(), 0;
  const Matrix3d Kinv = pair.K.inverse();
  Matrix3d F_true = Kinv.transpose() * tx * pair.R * Kinv;
  F_true /= F_true.norm();
  Matrix3d F = g.F / g.F.norm();
  if (F.cwiseProduct(F_true).sum() < 0) F = -F;
  EXPECT_LT((F - F_true).norm(), 0.05);
  // And its epipolar lines pass through the true correspondences.
  double total = 0;
  for (int i = 0; i < 200; ++i) {
    const Vector3d x1(pair.keypoints1[i].x, pair.keypoints1[i].y, 1);
    const Vector3d x2(pair.keypoints2[i].x, pair.keypoints2[i].y, 1);
    const Vector3d line = g.F * x1;
    total += std::abs(x2.dot(line)) / line.head<2>().norm();
  }
  EXPECT_LT(total / 200, 1.0);
}

INSTANTIATE_TEST_SUITE_P(AllMethods, VerificationMethods,
                         ::testing::Values(RansacMethod::kMsac, RansacMethod::kLoRansac,
                                           RansacMethod::kGraphCut));

TEST(GeometricVerification, PlanarSceneIsFlaggedPlanar) {
  const SyntheticPair pair = MakePair(150, 50, true, 8);
  const TwoViewGeometry g = VerifyTwoViewGeometry(pair.keypoints1, pair.keypoints2, pair.matches);
  EXPECT_EQ(g.config, TwoViewGeometry::kPlanarOrPanoramic);
  EXPECT_GE(CountTrueInliers(g, 150), 140);
  // H maps image 1 to image 2 on the plane.
  for (int i = 0; i < 150; i += 10) {
    const Vector3d x2 = g.H * Vector3d(pair.keypoints1[i].x, pair.keypoints1[i].y, 1);
    EXPECT_LT((x2.hnormalized() - Vector2d(pair.keypoints2[i].x, pair.keypoints2[i].y)).norm(),
              2.0);
  }
}

// F and H are judged each at its own threshold: an H held to 0.05 px (below the noise) no
// longer flags the plane, and an F held to 0.001 px no longer verifies the pair (beyond its own
// seven points a sample's F holds a plane point that close by chance, one in 300).
TEST(GeometricVerification, EachModelHasItsOwnThreshold) {
  const SyntheticPair pair = MakePair(150, 50, true, 8);
  VerificationOptions options;
  options.homography_max_error = 0.05;
  const TwoViewGeometry tight_h =
      VerifyTwoViewGeometry(pair.keypoints1, pair.keypoints2, pair.matches, options);
  EXPECT_EQ(tight_h.config, TwoViewGeometry::kUncalibrated);
  EXPECT_GE(CountTrueInliers(tight_h, 150), 120);
  options = {};
  options.max_error = 0.001;
  const TwoViewGeometry tight_f =
      VerifyTwoViewGeometry(pair.keypoints1, pair.keypoints2, pair.matches, options);
  EXPECT_EQ(tight_f.config, TwoViewGeometry::kDegenerate);
}

TEST(GeometricVerification, TooFewMatchesIsDegenerate) {
  const SyntheticPair pair = MakePair(10, 0, false, 9);
  const TwoViewGeometry g = VerifyTwoViewGeometry(pair.keypoints1, pair.keypoints2, pair.matches);
  EXPECT_EQ(g.config, TwoViewGeometry::kDegenerate);
  EXPECT_TRUE(g.inlier_matches.empty());
  // Pure outliers: no model gathers 15 inliers.
  const SyntheticPair noise = MakePair(0, 100, false, 10);
  const TwoViewGeometry h =
      VerifyTwoViewGeometry(noise.keypoints1, noise.keypoints2, noise.matches);
  EXPECT_EQ(h.config, TwoViewGeometry::kDegenerate);
  EXPECT_TRUE(h.inlier_matches.empty());
}

TEST(GeometricVerification, SameSeedSameResult) {
  const SyntheticPair pair = MakePair(100, 100, false, 11);
  for (RansacMethod method :
       {RansacMethod::kMsac, RansacMethod::kLoRansac, RansacMethod::kGraphCut}) {
    VerificationOptions options;
    options.method = method;
    options.seed = 123;
    const TwoViewGeometry a =
        VerifyTwoViewGeometry(pair.keypoints1, pair.keypoints2, pair.matches, options);
    const TwoViewGeometry b =
        VerifyTwoViewGeometry(pair.keypoints1, pair.keypoints2, pair.matches, options);
    EXPECT_EQ(a.inlier_matches, b.inlier_matches);
    EXPECT_EQ(a.F, b.F);
    EXPECT_EQ(a.H, b.H);
  }
}

TEST(GeometricVerification, OptionsAreChecked) {
  VerificationOptions options;
  EXPECT_NO_THROW(options.Check());
  options.mean_neighbours = 0;
  EXPECT_THROW(options.Check(), OptionError);
  options = {};
  options.spatial_coherence = 1.5;
  EXPECT_THROW(options.Check(), OptionError);
  options = {};
  options.max_error = -1;
  EXPECT_THROW(options.Check(), OptionError);
}

}  // namespace
}  // namespace varsfm
