#include "varsfm/scene/holdout.h"

#include <gtest/gtest.h>

#include "varsfm/util/error.h"

namespace varsfm {
namespace {

// Ten registered images whose ids run against their names' order, and one unregistered.
Reconstruction NamedImages() {
  Reconstruction rec;
  Camera camera = Camera::FromFocal(100, 100, 100);
  camera.camera_id = 1;
  rec.AddCamera(camera);
  for (image_t id = 1; id <= 11; ++id) {
    Image image;
    image.image_id = id;
    image.camera_id = 1;
    image.name = "img_" + std::to_string(20 - id) + ".jpg";  // id 1 is the last by name
    image.registered = id != 11;
    image.points2D.resize(2);
    rec.AddImage(image);
  }
  return rec;
}

TEST(Holdout, EveryNthRegisteredImageByName) {
  const Reconstruction rec = NamedImages();
  // Registered by name: img_10 (id 10), img_11 (9), ..., img_19 (1); every 4th from the first.
  EXPECT_EQ(HeldOutImageIds(rec, 4), (std::vector<image_t>{10, 6, 2}));
  EXPECT_EQ(HeldOutImageIds(rec, 8), (std::vector<image_t>{10, 2}));
  EXPECT_TRUE(HeldOutImageIds(rec, 0).empty());
}

TEST(Holdout, HeldOutImagesLeaveTheModelAndTheirTracks) {
  Reconstruction rec = NamedImages();
  const point3D_t point = rec.AddPoint3D(Eigen::Vector3d(0, 0, 5), {{10, 0}, {9, 0}, {8, 0}});
  EXPECT_EQ(HoldOutImages(&rec, 4), 3u);
  EXPECT_EQ(rec.NumRegisteredImages(), 7u);
  EXPECT_FALSE(rec.image(10).registered);
  EXPECT_FALSE(rec.image(10).points2D[0].HasPoint3D());
  EXPECT_EQ(rec.point3D(point).track.size(), 2u);
}

TEST(Holdout, CheckRefusesOneAndNegative) {
  EXPECT_NO_THROW(CheckHoldout(0));
  EXPECT_NO_THROW(CheckHoldout(2));
  EXPECT_THROW(CheckHoldout(1), Error);
  EXPECT_THROW(CheckHoldout(-3), Error);
}

}  // namespace
}  // namespace varsfm
