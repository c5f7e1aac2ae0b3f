// Source-view selection (dense/source_views.h) on a hand-made sparse model whose tracks say
// which image sees which part of a wall.
#include <gtest/gtest.h>

#include <map>
#include <vector>

#include "varsfm/dense/source_views.h"

namespace varsfm {
namespace {

constexpr int kWidth = 640, kHeight = 480;
constexpr double kFocal = 500;

// Image 1 looks at a wall at depth 10 from the origin. Images 2, 3 and 4 (x = 1.8, -1.8, 1.6:
// about 10, 10 and 9 degrees of triangulation angle) see only its left half, 100 points; image 5
// (x = -1.8) sees only its right half, 30 points; image 6 (x = 0.3, under 2 degrees: a near
// neighbour) sees, with image 1 alone, 20 points beyond the right half. Every image looks along
// +z.
Reconstruction HalfSeenWall() {
  Reconstruction rec;
  rec.AddCamera(Camera::FromFocal(kWidth, kHeight, kFocal));
  const double xs[] = {0.0, 1.8, -1.8, 1.6, -1.8, 0.3};
  for (int i = 0; i < 6; ++i) {
    Image image;
    image.image_id = i + 1;
    image.camera_id = rec.cameras().begin()->first;
    image.cam_from_world = Rigid3d(Eigen::Matrix3d::Identity(), Eigen::Vector3d(-xs[i], 0, 0));
    image.registered = true;
    rec.AddImage(image);
  }
  const auto add_point = [&](const Eigen::Vector3d& xyz, const std::vector<image_t>& views) {
    std::vector<TrackElement> track;
    for (image_t id : views) {
      Image& image = rec.image(id);
      track.push_back({id, static_cast<point2D_t>(image.points2D.size())});
      image.points2D.push_back({Eigen::Vector2d(kWidth / 2.0, kHeight / 2.0)});
    }
    rec.AddPoint3D(xyz, track);
  };
  for (int i = 0; i < 100; ++i) add_point({-4.0 + 0.03 * i, 0, 10}, {1, 2, 3, 4});
  for (int i = 0; i < 30; ++i) add_point({1.0 + 0.1 * i, 0, 10}, {1, 5});
  for (int i = 0; i < 20; ++i) add_point({4.0 + 0.05 * i, 0, 10}, {1, 6});
  return rec;
}

// The sources of every image of HalfSeenWall.
std::map<image_t, std::vector<image_t>> Sources(int num_sources, double redundant_point_weight,
                                                bool coverage_source = false) {
  SourceViewOptions options;
  options.num_source_views = num_sources;
  options.redundant_point_weight = redundant_point_weight;
  options.coverage_source = coverage_source;
  return SelectSourceViews(HalfSeenWall(), options);
}

TEST(SelectSourceViews, RankedByScoreWhenEveryPointCountsAlike) {
  // 3 sees the left half at the widest angles, then 2, then 4 (nearer to the reference); 5 sees
  // only 30 points.
  EXPECT_EQ(Sources(3, 1.0).at(1), (std::vector<image_t>{3, 2, 4}));
}

TEST(SelectSourceViews, LaterSourcesCoverWhatTheFirstOnesDoNotSee) {
  // Once 3 and 2 see the left half, a third view of it adds 3 % of its score, less than the
  // right half's 30 points: image 5, the only one to see them, comes in.
  const auto sources = Sources(3, 0.03);
  EXPECT_EQ(sources.at(1), (std::vector<image_t>{3, 2, 5}));
  // The sources of image 5 are 1 (the only image sharing its points): no other has 15 shared.
  EXPECT_EQ(sources.at(5), (std::vector<image_t>{1}));
}

TEST(SelectSourceViews, ANearNeighbourSeeingWhatNoSourceSeesComesInAsOneMore) {
  // Image 6's short baseline ranks it last; but it alone sees 20 of image 1's points, so it comes
  // in after the three sources. Image 5 has no view beyond image 1 to add.
  const auto sources = Sources(3, 0.03, true);
  EXPECT_EQ(sources.at(1), (std::vector<image_t>{3, 2, 5, 6}));
  EXPECT_EQ(sources.at(5), (std::vector<image_t>{1}));
  EXPECT_EQ(Sources(3, 0.03, false).at(1), (std::vector<image_t>{3, 2, 5}));
}

TEST(SelectSourceViews, TheExtraSourceSeesMostOfWhatTheOthersDoNot) {
  // With two sources (3, 2) both 5's 30 points and 6's 20 are unseen: the extra one is 5. With
  // four, 4 comes fourth (a third view of the left half still outscores 6's short baseline) and
  // 6 comes in after it.
  EXPECT_EQ(Sources(2, 0.03, true).at(1), (std::vector<image_t>{3, 2, 5}));
  EXPECT_EQ(Sources(4, 0.03, true).at(1), (std::vector<image_t>{3, 2, 5, 4, 6}));
}

TEST(SelectSourceViews, NoMoreSourcesThanCandidates) {
  const auto sources = Sources(16, 0.03, true);
  EXPECT_EQ(sources.at(1).size(), 5u);
  EXPECT_EQ(sources.at(2).size(), 3u);
}

TEST(OverlappingViews, EveryOtherViewWhileThereAreNoMoreThanTheCap) {
  const Reconstruction rec = HalfSeenWall();
  const std::vector<image_t> views = {1, 2, 3, 4, 5, 6};
  const auto overlapping = OverlappingViews(rec, views, 5);
  ASSERT_EQ(overlapping.size(), 6u);
  EXPECT_EQ(overlapping[0], (std::vector<uint32_t>{1, 2, 3, 4, 5}));
  EXPECT_EQ(overlapping[4], (std::vector<uint32_t>{0, 1, 2, 3, 5}));  // image 5: shares with 1 only
}

TEST(OverlappingViews, TheViewsSharingMostPointsBeyondTheCap) {
  const Reconstruction rec = HalfSeenWall();
  const std::vector<image_t> views = {1, 2, 3, 4, 5, 6};
  // Image 1 shares 100 points with each of 2, 3, 4, 30 with 5 and 20 with 6: with a cap of 4
  // image 6 (indices: 5) goes; with a cap of 2, 2 and 3 stay (ties go to the earlier views).
  EXPECT_EQ(OverlappingViews(rec, views, 4)[0], (std::vector<uint32_t>{1, 2, 3, 4}));
  EXPECT_EQ(OverlappingViews(rec, views, 2)[0], (std::vector<uint32_t>{1, 2}));
  // Image 2 shares 100 points with 1, 3 and 4 and none with 5 or 6: cap 4 fills with the
  // earliest view that shares nothing (image 5, index 4).
  EXPECT_EQ(OverlappingViews(rec, views, 4)[1], (std::vector<uint32_t>{0, 2, 3, 4}));
  // Image 5 shares its 30 points with image 1 alone.
  EXPECT_EQ(OverlappingViews(rec, views, 1)[4], (std::vector<uint32_t>{0}));
  // Only the views asked for count, in their order: image 1 among {6, 5, 1}.
  EXPECT_EQ(OverlappingViews(rec, {6, 5, 1}, 1)[2], (std::vector<uint32_t>{1}));
}

}  // namespace
}  // namespace varsfm
