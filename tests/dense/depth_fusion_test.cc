// Geometric consistency and fusion of exact depth maps: a plane seen by two views only.
#include <vector>

#include <gtest/gtest.h>

#include "varsfm/dense/depth_fusion.h"

namespace varsfm {
namespace {

constexpr int kSize = 40;

// View `index` at x = 0.3 index looking along +z at the plane z = 4: its exact depth map, every
// pixel of cost `cost`.
FusionView PlaneView(int index, float cost) {
  FusionView v;
  v.image_id = static_cast<image_t>(index + 1);
  v.K << 50, 0, kSize / 2.0, 0, 50, kSize / 2.0, 0, 0, 1;
  v.cam_from_world = Rigid3d(Eigen::Matrix3d::Identity(), Eigen::Vector3d(-0.3 * index, 0, 0));
  v.color = cv::Mat(kSize, kSize, CV_8UC3, cv::Scalar(10, 20, 30));
  v.map.width = v.map.height = kSize;
  v.map.depth.assign(kSize * kSize, 4.0f);
  v.map.normal.assign(v.map.depth.size(), -Eigen::Vector3f::UnitZ());
  v.map.cost.assign(v.map.depth.size(), cost);
  return v;
}

size_t Kept(const std::vector<FusionView>& views) {
  size_t n = 0;
  for (const FusionView& v : views)
    for (float d : v.map.depth) n += d > 0;
  return n;
}

TEST(DepthFusion, TwoViewSurfaceIsKeptOnlyWhereItsCostAllows) {
  // Without the exception a depth needs two confirming views: two views of the plane keep
  // nothing.
  std::vector<FusionView> views = {PlaneView(0, 0.1f), PlaneView(1, 0.1f)};
  DepthFusionOptions options;
  options.two_view_max_cost = 0;
  FilterByGeometricConsistency(&views, options);
  EXPECT_EQ(Kept(views), 0u);

  // With two_view_max_cost the confident depths stand on one confirming view and fuse with two;
  // the overlap of the two views is 40 - 0.3 x 50 / 4 = 36.25 columns.
  options.two_view_max_cost = 0.2;
  views = {PlaneView(0, 0.1f), PlaneView(1, 0.1f)};
  FilterByGeometricConsistency(&views, options);
  const size_t kept = Kept(views);
  EXPECT_GE(kept, 2u * 36 * kSize);
  EXPECT_LE(kept, 2u * 37 * kSize);
  DenseVisibility visibility;
  const PointCloud cloud = FuseDepthMaps(views, options, &visibility);
  ASSERT_GE(cloud.points.size(), 35u * kSize);
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    EXPECT_NEAR(cloud.points[i].z(), 4.0, 1e-9);
    EXPECT_EQ(visibility[i], (std::vector<image_t>{1, 2}));
  }

  // Depths above that cost keep the default counts.
  views = {PlaneView(0, 0.3f), PlaneView(1, 0.3f)};
  FilterByGeometricConsistency(&views, options);
  EXPECT_EQ(Kept(views), 0u);
}

TEST(DepthFusion, DepthsAreCheckedAndFusedWithTheOverlappingViewsOnly) {
  // Three exact views of the plane: every depth has two confirming views and fuses with three.
  DepthFusionOptions options;
  options.two_view_max_cost = 0;
  std::vector<FusionView> views = {PlaneView(0, 0.1f), PlaneView(1, 0.1f), PlaneView(2, 0.1f)};
  FilterByGeometricConsistency(&views, options);
  EXPECT_GT(Kept(views), 0u);
  const PointCloud all = FuseDepthMaps(views, options);
  ASSERT_GT(all.points.size(), 0u);

  // The same with the lists naming every other view: the same depths and points.
  std::vector<FusionView> listed = {PlaneView(0, 0.1f), PlaneView(1, 0.1f), PlaneView(2, 0.1f)};
  listed[0].overlapping = {1, 2};
  listed[1].overlapping = {0, 2};
  listed[2].overlapping = {0, 1};
  FilterByGeometricConsistency(&listed, options);
  EXPECT_EQ(Kept(listed), Kept(views));
  const PointCloud same = FuseDepthMaps(listed, options);
  ASSERT_EQ(same.points.size(), all.points.size());
  for (size_t i = 0; i < all.points.size(); ++i) EXPECT_EQ(same.points[i], all.points[i]);

  // Each view checked against one other only: no depth has the two confirmations it needs.
  listed = {PlaneView(0, 0.1f), PlaneView(1, 0.1f), PlaneView(2, 0.1f)};
  listed[0].overlapping = {1};
  listed[1].overlapping = {2};
  listed[2].overlapping = {0};
  FilterByGeometricConsistency(&listed, options);
  EXPECT_EQ(Kept(listed), 0u);

  // Fusion joins the listed views only: view 0 listing view 1 alone makes points of two views.
  listed = {PlaneView(0, 0.1f), PlaneView(1, 0.1f), PlaneView(2, 0.1f)};
  listed[0].overlapping = {1};
  options.min_fused_views = 2;
  DenseVisibility visibility;
  const PointCloud pairs = FuseDepthMaps(listed, options, &visibility);
  ASSERT_GT(pairs.points.size(), 0u);
  EXPECT_EQ(visibility.front(), (std::vector<image_t>{1, 2}));
}

}  // namespace
}  // namespace varsfm
