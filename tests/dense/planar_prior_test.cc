// The planar prior (Xu & Tao 2020) with exact truth: a slanted wall whose middle is blank (no
// texture at all), seen by five cameras. The blank area has no depth after a photometric pass;
// the planes of the textured pixels around it carry the wall across it.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "varsfm/dense/depth_fusion.h"
#include "varsfm/dense/patchmatch.h"
#include "varsfm/dense/planar_prior.h"

namespace varsfm {
namespace {

constexpr int kWidth = 160, kHeight = 120;
constexpr double kFocal = 180;

// The wall n^T X = c in the reference's (the world's) frame, 30 deg from fronto-parallel, depth
// 5 at the image centre.
const Eigen::Vector3d kWallNormal = Eigen::Vector3d(0.5, 0, -std::sqrt(3.0) / 2);
const double kWallOffset = kWallNormal.dot(Eigen::Vector3d(0, 0, 5));

Eigen::Matrix3d Intrinsics() {
  Eigen::Matrix3d K;
  K << kFocal, 0, kWidth / 2.0, 0, kFocal, kHeight / 2.0, 0, 0, 1;
  return K;
}

// Textured (several waves, 0.3 peak to peak) but blank inside a disc of radius 0.7 round the
// wall point the reference sees at its centre: about 25 px, over twice the 11 px window.
bool Blank(const Eigen::Vector3d& X) { return (X - Eigen::Vector3d(0, 0, 5)).norm() < 0.7; }
double WallIntensity(const Eigen::Vector3d& X) {
  if (Blank(X)) return 0.5;
  return 0.5 + 0.08 * std::sin(9.1 * X.x() + 3.3 * X.y()) +
         0.05 * std::sin(6.3 * X.y() - 4.7 * X.x()) +
         0.03 * std::sin(17.9 * X.x() + 13.1 * X.y() + 1.1);
}

Eigen::Vector3d WallPoint(const Rigid3d& cam_from_world, double u, double v) {
  const Eigen::Vector3d d =
      cam_from_world.R().transpose() * (Intrinsics().inverse() * Eigen::Vector3d(u, v, 1));
  const Eigen::Vector3d centre = cam_from_world.Center();
  return centre + d * ((kWallOffset - kWallNormal.dot(centre)) / kWallNormal.dot(d));
}

PatchMatchView RenderWall(const Rigid3d& cam_from_world) {
  PatchMatchView v;
  v.K = Intrinsics();
  v.cam_from_world = cam_from_world;
  v.gray.create(kHeight, kWidth, CV_32F);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      double sum = 0;  // 3x3 samples a pixel (anti-aliasing)
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i)
          sum += WallIntensity(WallPoint(cam_from_world, x + (i + 0.5) / 3, y + (j + 0.5) / 3));
      v.gray.at<float>(y, x) = static_cast<float>(sum / 9);
    }
  return v;
}

std::vector<PatchMatchView> WallViews() {
  std::vector<PatchMatchView> views;
  for (const Eigen::Vector3d& c :
       {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(-0.6, 0, 0), Eigen::Vector3d(0.6, 0, 0),
        Eigen::Vector3d(0, -0.5, 0.2), Eigen::Vector3d(0, 0.5, -0.2)})
    views.push_back(RenderWall(Rigid3d(Eigen::Matrix3d::Identity(), -c)));
  return views;
}

// The source views of view r: the four others.
std::vector<uint32_t> OtherViews(uint32_t r) {
  std::vector<uint32_t> views = {0, 1, 2, 3, 4};
  views.erase(views.begin() + r);
  return views;
}

double TrueDepth(double u, double v) { return WallPoint(Rigid3d(), u, v).z(); }

// Of the reference's pixels inside (or outside) the blank disc: the share within `tolerance`
// (relative) of the true depth.
double ShareWithin(const DepthMap& map, bool blank, double tolerance = 0.01) {
  size_t good = 0, n = 0;
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) {
      if (Blank(WallPoint(Rigid3d(), x + 0.5, y + 0.5)) != blank) continue;
      ++n;
      const double d = map.depth[map.Index(x, y)], truth = TrueDepth(x + 0.5, y + 0.5);
      if (d > 0 && std::abs(d - truth) <= tolerance * truth) ++good;
    }
  return static_cast<double>(good) / static_cast<double>(n);
}

TEST(PlanarPrior, TrianglesOfExactAnchorsReproduceThePlane) {
  // Exact depths at 4 pixels near the corners and one in the middle, nothing else.
  DepthMap map;
  map.width = kWidth, map.height = kHeight;
  map.depth.assign(kWidth * kHeight, 0);
  map.normal.assign(map.depth.size(), Eigen::Vector3f::Zero());
  map.cost.assign(map.depth.size(), 2.0f);
  for (const auto& [x, y] :
       std::vector<std::pair<int, int>>{{10, 10}, {149, 12}, {12, 109}, {147, 107}, {80, 60}}) {
    map.depth[map.Index(x, y)] = static_cast<float>(TrueDepth(x + 0.5, y + 0.5));
    map.cost[map.Index(x, y)] = 0.05f;
  }
  PlanarPriorOptions options;
  options.max_edge_fraction = 1.0;
  const DepthMap prior = BuildPlanarPrior(map, Intrinsics(), options);
  size_t inside = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const size_t i = prior.Index(x, y);
      const bool in_hull = x >= 16 && x <= 143 && y >= 16 && y <= 103;
      const bool out_of_box = x < 10 || x > 149 || y < 10 || y > 109;
      if (out_of_box) EXPECT_EQ(prior.depth[i], 0) << x << " " << y;
      if (!in_hull) continue;
      ASSERT_GT(prior.depth[i], 0) << x << " " << y;
      ++inside;
      EXPECT_NEAR(prior.depth[i], TrueDepth(x + 0.5, y + 0.5), 1e-4 * TrueDepth(x + 0.5, y + 0.5));
      EXPECT_NEAR(prior.normal[i].dot(kWallNormal.cast<float>()), 1.0f, 1e-5f);
    }
  EXPECT_GT(inside, 10000u);
  // Sides longer than a quarter of the image are left out: no triangle is kept.
  options.max_edge_fraction = 0.25;
  const DepthMap none = BuildPlanarPrior(map, Intrinsics(), options);
  for (float d : none.depth) EXPECT_EQ(d, 0);
}

TEST(PlanarPrior, CarriesTheWallAcrossItsBlankMiddle) {
  const std::vector<PatchMatchView> views = WallViews();
  PatchMatchInit init;
  init.min_depth = 3;
  init.max_depth = 9;
  PatchMatchOptions options;
  const uint32_t n = static_cast<uint32_t>(views.size());
  // Every view's first pass; the anchors are their confident depths that two other views
  // confirm, as MultiViewStereo chooses them (nearly flat windows at the blank disc's edge match
  // wrong planes at low cost by chance; other views do not confirm those).
  std::vector<FusionView> anchors(n);
  for (uint32_t r = 0; r < n; ++r) {
    anchors[r].image_id = r + 1;
    anchors[r].K = views[r].K;
    anchors[r].cam_from_world = views[r].cam_from_world;
    anchors[r].map = EstimateDepthMap(views, r, OtherViews(r), init, options, 7 + r, false);
  }
  const DepthMap first = anchors[0].map;
  PlanarPriorOptions planar;
  planar.max_edge_fraction = 0.5;  // the disc is a third of the image wide
  for (FusionView& v : anchors)
    for (size_t i = 0; i < v.map.depth.size(); ++i)
      if (v.map.cost[i] > planar.anchor_max_cost) v.map.depth[i] = 0;
  DepthFusionOptions strict;
  strict.two_view_max_cost = 0;
  FilterByGeometricConsistency(&anchors, strict);
  PatchMatchInit planar_init = init;
  planar_init.planar = BuildPlanarPrior(anchors[0].map, views[0].K, planar);
  const DepthMap refined =
      RefineDepthMap(views, 0, OtherViews(0), {}, first, planar_init, options, 8, 2);

  DepthMap photometric = first;
  for (size_t i = 0; i < photometric.depth.size(); ++i)
    if (photometric.cost[i] > options.max_cost) photometric.depth[i] = 0;
  const double blank_first = ShareWithin(photometric, true);
  const double blank_refined = ShareWithin(refined, true);
  const double textured_first = ShareWithin(photometric, false);
  const double textured_refined = ShareWithin(refined, false);
  const double blank_first_5 = ShareWithin(photometric, true, 0.05);
  const double blank_refined_5 = ShareWithin(refined, true, 0.05);
  std::printf(
      "blank disc within 1 %%: %.3f -> %.3f (prior %.3f), within 5 %%: %.3f -> %.3f; textured "
      "within 1 %%: %.3f -> %.3f\n",
      blank_first, blank_refined, ShareWithin(planar_init.planar, true), blank_first_5,
      blank_refined_5, textured_first, textured_refined);
  // Measured: 0.269 -> 0.639 within 1 %; the prior planes rest on anchors up to 3 % off (a few
  // of the confirmed depths at the disc's edge), so not every blank pixel is within 1 %.
  EXPECT_GT(blank_refined, blank_first + 0.3);
  EXPECT_GT(blank_refined_5, 0.95);
  EXPECT_GE(textured_refined, textured_first - 0.01);
  // Same bits for the same seed.
  const DepthMap again =
      RefineDepthMap(views, 0, OtherViews(0), {}, first, planar_init, options, 8, 2);
  EXPECT_EQ(refined.depth, again.depth);
}

}  // namespace
}  // namespace varsfm
