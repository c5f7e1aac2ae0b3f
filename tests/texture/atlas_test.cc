// Shelf packing places every chart inside its page and no two charts overlap.
#include <gtest/gtest.h>

#include <random>

#include "varsfm/texture/atlas.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

void ExpectValid(const std::vector<AtlasRect>& rects, const AtlasLayout& layout) {
  ASSERT_EQ(layout.placements.size(), rects.size());
  for (size_t i = 0; i < rects.size(); ++i) {
    const AtlasPlacement& p = layout.placements[i];
    ASSERT_GE(p.page, 0);
    ASSERT_LT(p.page, static_cast<int>(layout.pages.size()));
    EXPECT_GE(p.x, 0);
    EXPECT_GE(p.y, 0);
    EXPECT_LE(p.x + rects[i].width, layout.pages[p.page].width);
    EXPECT_LE(p.y + rects[i].height, layout.pages[p.page].height);
  }
  for (size_t i = 0; i < rects.size(); ++i) {
    for (size_t j = i + 1; j < rects.size(); ++j) {
      const AtlasPlacement &a = layout.placements[i], &b = layout.placements[j];
      if (a.page != b.page) continue;
      const bool apart = a.x + rects[i].width <= b.x || b.x + rects[j].width <= a.x ||
                         a.y + rects[i].height <= b.y || b.y + rects[j].height <= a.y;
      EXPECT_TRUE(apart) << "charts " << i << " and " << j << " overlap";
    }
  }
}

TEST(Atlas, ChartsDoNotOverlapAndWasteLittle) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> size(1, 120);
  std::vector<AtlasRect> rects(800);
  double area = 0;
  for (AtlasRect& r : rects) {
    r = {size(rng), size(rng)};
    area += r.width * r.height;
  }
  const AtlasLayout layout = PackRectangles(rects);
  ASSERT_EQ(layout.pages.size(), 1u);
  ExpectValid(rects, layout);
  const double page = static_cast<double>(layout.pages[0].width) * layout.pages[0].height;
  EXPECT_GT(area / page, 0.6) << "shelf packing should fill most of the page";
}

TEST(Atlas, OverflowStartsNewPages) {
  std::vector<AtlasRect> rects(50, AtlasRect{100, 100});
  const AtlasLayout layout = PackRectangles(rects, 256);
  EXPECT_GT(layout.pages.size(), 1u);
  ExpectValid(rects, layout);
  for (const AtlasRect& page : layout.pages) {
    EXPECT_LE(page.width, 256);
    EXPECT_LE(page.height, 256);
  }
}

TEST(Atlas, NegativeSizeIsAnError) { EXPECT_THROW(PackRectangles({AtlasRect{-1, 4}}), Error); }

}  // namespace
}  // namespace varsfm
