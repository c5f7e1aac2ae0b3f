#include <gtest/gtest.h>

#include "estimators/test_scenes.h"
#include "varsfm/estimators/essential_5pt.h"
#include "varsfm/estimators/homography_4pt.h"
#include "varsfm/estimators/two_view_estimators.h"
#include "varsfm/geometry/essential.h"
#include "varsfm/geometry/fundamental.h"

namespace varsfm {
namespace {

// Three views of a plane, zooming from 900 to 1600 px.
SyntheticOptions ZoomingPlane() {
  SyntheticOptions o;
  o.structure = SyntheticOptions::Structure::kPlane;
  o.num_images = 3;
  o.focal_start = 900;
  o.focal_end = 1600;
  return o;
}

TEST(Homography4pt, ExactMinimalSolveAgreesWithTheDLT) {
  const testing::Matches m = testing::PairMatches(GenerateSyntheticScene(ZoomingPlane()), 0, 2);
  ASSERT_GE(m.x1.size(), 40u);
  for (size_t first = 0; first + 4 <= 40; first += 4) {
    const std::vector<Eigen::Vector2d> y1(m.x1.begin() + first, m.x1.begin() + first + 4);
    const std::vector<Eigen::Vector2d> y2(m.x2.begin() + first, m.x2.begin() + first + 4);
    Eigen::Matrix3d H, H_dlt;
    ASSERT_TRUE(Homography4pt(y1, y2, &H));
    ASSERT_TRUE(HomographyDLT(y1, y2, &H_dlt));
    // Both unit norm: equal up to sign.
    EXPECT_LT(std::min((H - H_dlt).norm(), (H + H_dlt).norm()), 1e-7);
    for (size_t i = 0; i < m.x1.size(); ++i)
      EXPECT_LT(((H * m.x1[i].homogeneous()).hnormalized() - m.x2[i]).norm(), 1e-7);
  }
  // Three of the four on a line: no homography.
  const std::vector<Eigen::Vector2d> line1{{0, 0}, {100, 100}, {200, 200}, {50, 300}};
  const std::vector<Eigen::Vector2d> line2{{10, 0}, {110, 90}, {210, 180}, {40, 310}};
  Eigen::Matrix3d H;
  EXPECT_FALSE(Homography4pt(line1, line2, &H));
  EXPECT_FALSE(
      Homography4pt({line1.begin(), line1.begin() + 3}, {line2.begin(), line2.begin() + 3}, &H));
}

TEST(HomographyDLT, ExactOnPlanarScene) {
  SyntheticOptions o = ZoomingPlane();
  const SyntheticScene scene = GenerateSyntheticScene(o);
  const testing::Matches m = testing::PairMatches(scene, 0, 2);
  for (const size_t n : {size_t{4}, m.x1.size()}) {
    const std::vector<Eigen::Vector2d> y1(m.x1.begin(), m.x1.begin() + n);
    const std::vector<Eigen::Vector2d> y2(m.x2.begin(), m.x2.begin() + n);
    Eigen::Matrix3d H;
    ASSERT_TRUE(HomographyDLT(y1, y2, &H));
    for (size_t i = 0; i < m.x1.size(); ++i)
      EXPECT_LT(((H * m.x1[i].homogeneous()).hnormalized() - m.x2[i]).norm(), 1e-8);
  }
  o.noise_sigma = 0.5;
  o.outlier_ratio = 0.3;
  const SyntheticScene noisy = GenerateSyntheticScene(o);
  const testing::Matches mn = testing::PairMatches(noisy, 0, 2);
  RansacOptions options;
  // The one-sided transfer error carries the noise of both images, the first magnified by
  // the zoom (~1.6x): sigma ~ 0.5 sqrt(1.6^2 + 1) ~ 0.95 px, so 4 px is ~4 sigma.
  options.max_error = 4.0;
  const auto report = EstimateHomography(mn.x1, mn.x2, options);
  ASSERT_TRUE(report.success);
  double recall, precision;
  testing::InlierQuality(report.inlier_mask, mn.outlier, &recall, &precision);
  EXPECT_GT(recall, 0.95);
  EXPECT_GT(precision, 0.95);
}

struct NormalizedPair {
  std::vector<Eigen::Vector2d> x1, x2;
  std::vector<char> outlier;
  Eigen::Matrix3d E;
};

NormalizedPair MakePair(double noise, double outliers) {
  SyntheticOptions o;
  o.num_images = 3;
  o.focal_start = 1000;
  o.focal_end = 1500;
  o.noise_sigma = noise;
  o.outlier_ratio = outliers;
  const SyntheticScene scene = GenerateSyntheticScene(o);
  const testing::Matches m = testing::PairMatches(scene, 0, 2);
  NormalizedPair p;
  for (size_t i = 0; i < m.x1.size(); ++i) {
    p.x1.push_back(scene.cameras[0].ImageToNormalized(m.x1[i]));
    p.x2.push_back(scene.cameras[2].ImageToNormalized(m.x2[i]));
  }
  p.outlier = m.outlier;
  p.E = EssentialFromPose(scene.poses[2] * scene.poses[0].Inverse());
  p.E /= p.E.norm();
  return p;
}

TEST(Essential5pt, ReturnsTrueEssentialAmongSolutions) {
  const NormalizedPair p = MakePair(0.0, 0.0);
  for (int start = 0; start + 5 <= 100; start += 5) {
    const std::vector<Eigen::Vector2d> y1(p.x1.begin() + start, p.x1.begin() + start + 5);
    const std::vector<Eigen::Vector2d> y2(p.x2.begin() + start, p.x2.begin() + start + 5);
    std::vector<Eigen::Matrix3d> models;
    ASSERT_GE(Essential5pt(y1, y2, &models), 1);
    EXPECT_LE(models.size(), 10u);
    double best = 1e300;
    for (const auto& E : models) best = std::min({best, (E - p.E).norm(), (E + p.E).norm()});
    EXPECT_LT(best, 1e-8) << start;
  }
}

TEST(EstimateEssentialMatrix, FindsModelWithOutliersAndPoseFollows) {
  const NormalizedPair p = MakePair(0.5, 0.3);
  RansacOptions options;
  options.max_error = 2.0 / 1250.0;  // ~2 px in normalised units
  const auto report = EstimateEssentialMatrix(p.x1, p.x2, options);
  ASSERT_TRUE(report.success);
  double recall, precision;
  testing::InlierQuality(report.inlier_mask, p.outlier, &recall, &precision);
  EXPECT_GT(recall, 0.95);
  EXPECT_GT(precision, 0.95);
  const double dist = std::min((report.model - p.E).norm(), (report.model + p.E).norm());
  EXPECT_LT(dist, 0.05);
}

}  // namespace
}  // namespace varsfm
