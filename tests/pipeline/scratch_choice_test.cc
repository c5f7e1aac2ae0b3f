#include "varsfm/pipeline/scratch_choice.h"

#include <limits>

#include <gtest/gtest.h>

#include "support/test_data.h"

namespace varsfm {
namespace {

TEST(ScratchChoice, ViewBytesCountTheRegisteredViewsAtTheirScaledSize) {
  Reconstruction rec;
  Camera wide = Camera::FromFocal(1600, 1200, 1000), small = Camera::FromFocal(400, 300, 300);
  wide.camera_id = 1, small.camera_id = 2;
  rec.AddCamera(wide), rec.AddCamera(small);
  for (image_t id : {1, 2, 3}) {
    Image image;
    image.image_id = id;
    image.camera_id = id == 2 ? 2 : 1;
    image.registered = id != 3;  // not registered: not densified, not textured
    rec.AddImage(image);
  }
  // 1600 x 1200 scaled to 800 x 600; 400 x 300 is never enlarged.
  EXPECT_EQ(ViewBytes(rec, 800, 27), (800u * 600 + 400 * 300) * 27);
}

TEST(ScratchChoice, ScratchMemoryOnlyWhereTheViewsWouldCrowdMemory) {
  testing::TempDir tmp("scratch_choice");
  // Views that fit: the heap.
  EXPECT_TRUE(ScratchFolderFor(tmp.path() / "out", 1 << 20, "views").empty());
  // Views larger than any memory: the output's disk, before the output folder exists.
  EXPECT_EQ(
      ScratchFolderFor(tmp.path() / "out" / "run", std::numeric_limits<size_t>::max(), "views"),
      tmp.path());
}

}  // namespace
}  // namespace varsfm
