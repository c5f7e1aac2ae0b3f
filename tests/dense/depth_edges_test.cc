// Foreground fattening's clean-up on maps of exact layout: a surface beside the open background
// (the sky past a roofline), a hole inside a surface, a thread of missing pixels, the border.
#include <gtest/gtest.h>

#include "varsfm/dense/depth_edges.h"
#include "varsfm/util/option_check.h"

namespace varsfm {
namespace {

// width x height (40 x 30 unless given) at depth 2, except `no_depth(x, y)`.
template <typename F>
DepthMap Map(F no_depth, int width = 40, int height = 30) {
  DepthMap map;
  map.width = width, map.height = height;
  map.depth.assign(map.width * map.height, 2.0f);
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x)
      if (no_depth(x, y)) map.depth[map.Index(x, y)] = 0;
  return map;
}

size_t Dropped(const DepthMap& before, const DepthMap& after) {
  size_t n = 0;
  for (size_t i = 0; i < before.depth.size(); ++i) n += before.depth[i] > 0 && after.depth[i] == 0;
  return n;
}

TEST(DepthEdges, DropsTheDepthsBesideTheOpenBackground) {
  const DepthMap before = Map([](int x, int) { return x >= 25; });  // sky from column 25 on
  DepthMap map = before;
  EXPECT_EQ(ErodeDepthEdges(DepthEdgeOptions{.erosion_px = 3}, &map), 3u * 30u);
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < 25; ++x)
      EXPECT_EQ(map.depth[map.Index(x, y)], x < 22 ? 2.0f : 0.0f) << x << ", " << y;
  EXPECT_EQ(Dropped(before, map), 90u);
}

TEST(DepthEdges, ASmallHoleInsideASurfaceIsLeftAlone) {
  // A blank 8 x 8 patch of a 100 x 100 wall (0.64 % of it): fattened by the wall, at the wall's
  // depth.
  const DepthMap before =
      Map([](int x, int y) { return x >= 40 && x < 48 && y >= 40 && y < 48; }, 100, 100);
  DepthMap map = before;
  EXPECT_EQ(ErodeDepthEdges(DepthEdgeOptions{.erosion_px = 4}, &map), 0u);
  EXPECT_EQ(map.depth, before.depth);
}

TEST(DepthEdges, ALargeEnclosedGapIsOpenBackground) {
  // 20 x 20 (4 %) without depth inside the map: the sky between two towers and a roof.
  const DepthMap before =
      Map([](int x, int y) { return x >= 40 && x < 60 && y >= 40 && y < 60; }, 100, 100);
  DepthMap map = before;
  EXPECT_EQ(ErodeDepthEdges(DepthEdgeOptions{.erosion_px = 2}, &map), 24u * 24u - 20u * 20u);
  EXPECT_EQ(map.depth[map.Index(38, 50)], 0.0f);
  EXPECT_EQ(map.depth[map.Index(37, 50)], 2.0f);
  // Counted as open only when it reaches the border: left alone.
  map = before;
  EXPECT_EQ(ErodeDepthEdges(DepthEdgeOptions{.erosion_px = 2, .large_gap_fraction = 0}, &map), 0u);
}

TEST(DepthEdges, AThreadOfMissingPixelsDoesNotOpenAHole) {
  // The small hole, joined to the border by a line two pixels wide.
  const DepthMap before = Map(
      [](int x, int y) {
        return (x >= 40 && x < 48 && y >= 40 && y < 48) || (y >= 43 && y < 45 && x < 40);
      },
      100, 100);
  DepthMap map = before;
  EXPECT_EQ(ErodeDepthEdges(DepthEdgeOptions{.erosion_px = 2}, &map), 0u);
  // With gaps of any width counted, the hole is open background.
  EXPECT_GT(ErodeDepthEdges(DepthEdgeOptions{.erosion_px = 2, .min_gap_px = 1}, &map), 0u);
  EXPECT_EQ(map.depth[map.Index(49, 42)], 0.0f) << "beside the hole";
  EXPECT_EQ(map.depth[map.Index(80, 80)], 2.0f) << "far from it";
}

TEST(DepthEdges, NoErosionLeavesTheMap) {
  const DepthMap before = Map([](int x, int) { return x >= 25; });
  DepthMap map = before;
  EXPECT_EQ(ErodeDepthEdges(DepthEdgeOptions{.erosion_px = 0}, &map), 0u);
  EXPECT_EQ(map.depth, before.depth);
}

TEST(DepthEdges, OptionsAreChecked) {
  EXPECT_THROW((DepthEdgeOptions{.erosion_px = -1}.Check()), OptionError);
  EXPECT_THROW((DepthEdgeOptions{.erosion_px = 2, .min_gap_px = 0}.Check()), OptionError);
  EXPECT_THROW((DepthEdgeOptions{.large_gap_fraction = 1.5}.Check()), OptionError);
  EXPECT_NO_THROW(DepthEdgeOptions{}.Check());
}

}  // namespace
}  // namespace varsfm
