#include "varsfm/ba/intrinsics_groups.h"

#include <gtest/gtest.h>

namespace varsfm {
namespace {

// (focal, id) ascending, ids 1..n, and one image per camera.
struct OneSize {
  std::vector<std::pair<double, camera_t>> by_focal;
  std::map<camera_t, int> images_of_camera;
};

OneSize CamerasAt(const std::vector<double>& focals) {
  OneSize s;
  for (size_t i = 0; i < focals.size(); ++i) {
    const camera_t id = static_cast<camera_t>(i + 1);
    s.by_focal.emplace_back(focals[i], id);
    s.images_of_camera[id] = 1;
  }
  return s;
}

TEST(ZoomBandGroups, RatioZeroIsOneGroupForTheSize) {
  const OneSize s = CamerasAt({900, 1000, 1500, 2000});
  EXPECT_EQ(ZoomBandGroups(s.by_focal, s.images_of_camera, 0.0, 3), (std::vector<int>{0, 0, 0, 0}));
}

TEST(ZoomBandGroups, TooFewImagesFormNoGroup) {
  const OneSize s = CamerasAt({900, 910});
  EXPECT_TRUE(ZoomBandGroups(s.by_focal, s.images_of_camera, 1.1, 3).empty());
}

TEST(ZoomBandGroups, EachZoomBandOfThreeImagesIsItsOwnGroup) {
  // Bands start at 900 and 1400: a band takes up to 1.1 x its shortest focal length.
  const OneSize s = CamerasAt({900, 950, 990, 1400, 1450, 1500});
  EXPECT_EQ(ZoomBandGroups(s.by_focal, s.images_of_camera, 1.1, 3),
            (std::vector<int>{0, 0, 0, 1, 1, 1}));
}

TEST(ZoomBandGroups, ABandStartsWhereThePreviousOneStopped) {
  // 900-990 is one band; 1000 is beyond 1.1 x 900 and starts the next, which takes 1090 too
  // (within 1.1 x 1000) though it is 1.21 x the first band's start.
  const OneSize s = CamerasAt({900, 950, 990, 1000, 1050, 1090});
  EXPECT_EQ(ZoomBandGroups(s.by_focal, s.images_of_camera, 1.1, 3),
            (std::vector<int>{0, 0, 0, 1, 1, 1}));
}

TEST(ZoomBandGroups, ASmallBandJoinsTheNearestLargeBandByFocalRatio) {
  // Bands: [900, 920, 940] (large), [1200] (small), [1500, 1520, 1540] (large), [3000] (small).
  // 1200 / 940 = 1.277 against 1500 / 1200 = 1.25: the upper band is nearer.
  const OneSize s = CamerasAt({900, 920, 940, 1200, 1500, 1520, 1540, 3000});
  const std::vector<int> groups = ZoomBandGroups(s.by_focal, s.images_of_camera, 1.1, 3);
  EXPECT_EQ(groups, (std::vector<int>{0, 0, 0, 2, 2, 2, 2, 2}));
}

TEST(ZoomBandGroups, WithoutALargeBandTheSizeIsOneGroup) {
  const OneSize s = CamerasAt({900, 1200, 1600, 2100});
  EXPECT_EQ(ZoomBandGroups(s.by_focal, s.images_of_camera, 1.1, 3), (std::vector<int>{0, 0, 0, 0}));
}

TEST(ZoomBandGroups, ACameraCountsItsImages) {
  // One camera of four images (`--intrinsics shared`) is a large band on its own.
  OneSize s = CamerasAt({900, 1500});
  s.images_of_camera[1] = 4;
  EXPECT_EQ(ZoomBandGroups(s.by_focal, s.images_of_camera, 1.1, 3), (std::vector<int>{0, 0}));
  s.images_of_camera[2] = 3;
  EXPECT_EQ(ZoomBandGroups(s.by_focal, s.images_of_camera, 1.1, 3), (std::vector<int>{0, 1}));
}

// A model of one image per camera: `sizes_and_focals` gives each camera's width, height, focal.
Reconstruction ModelOf(const std::vector<std::tuple<int, int, double>>& sizes_and_focals) {
  Reconstruction rec;
  image_t id = 1;
  for (const auto& [w, h, f] : sizes_and_focals) {
    Camera camera = Camera::FromFocal(w, h, f);
    camera.camera_id = id;
    rec.AddCamera(camera);
    Image image;
    image.image_id = id;
    image.name = std::to_string(id) + ".jpg";
    image.camera_id = id;
    image.registered = true;
    rec.AddImage(image);
    ++id;
  }
  return rec;
}

IntrinsicsOptions PrincipalPointPerBand() {
  IntrinsicsOptions options;
  options.refine_principal_point = true;
  options.shared_per_size = {Camera::kU0, Camera::kV0};
  options.max_shared_focal_ratio = 1.1;
  return options;
}

TEST(SharedGroupMembers, GroupsArePerImageSizeAndZoomBand) {
  const Reconstruction rec = ModelOf({{640, 480, 500},
                                      {640, 480, 510},
                                      {640, 480, 520},
                                      {640, 480, 800},
                                      {640, 480, 810},
                                      {640, 480, 820},
                                      {320, 240, 500},
                                      {320, 240, 505},
                                      {320, 240, 510}});
  const std::map<camera_t, IntrinsicsGroupKey> members =
      SharedGroupMembers(PrincipalPointPerBand(), {}, {1, 2, 3, 4, 5, 6, 7, 8, 9}, rec);
  ASSERT_EQ(members.size(), 9u);
  for (const camera_t id : {1, 2, 3}) EXPECT_EQ(members.at(id), IntrinsicsGroupKey(640, 480, 0));
  for (const camera_t id : {4, 5, 6}) EXPECT_EQ(members.at(id), IntrinsicsGroupKey(640, 480, 1));
  for (const camera_t id : {7, 8, 9}) EXPECT_EQ(members.at(id), IntrinsicsGroupKey(320, 240, 0));
}

TEST(SharedGroupMembers, ConstantCamerasAndSmallSizesTakeNoSharedBlock) {
  const Reconstruction rec =
      ModelOf({{640, 480, 500}, {640, 480, 510}, {640, 480, 520}, {320, 240, 500}});
  // Camera 3 held: its size keeps two variable images, too few to share.
  EXPECT_TRUE(SharedGroupMembers(PrincipalPointPerBand(), {3}, {1, 2, 3, 4}, rec).empty());
  EXPECT_EQ(SharedGroupMembers(PrincipalPointPerBand(), {}, {1, 2, 3, 4}, rec).size(), 3u);
  IntrinsicsOptions nothing_shared = PrincipalPointPerBand();
  nothing_shared.shared_per_size.clear();
  EXPECT_TRUE(SharedGroupMembers(nothing_shared, {}, {1, 2, 3, 4}, rec).empty());
}

}  // namespace
}  // namespace varsfm
