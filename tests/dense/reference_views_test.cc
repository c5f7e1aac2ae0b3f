// Which views get a depth map (dense/reference_views.h), on hand-made sparse models whose tracks
// say which image sees which point.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "varsfm/dense/reference_views.h"

namespace varsfm {
namespace {

// `num_images` registered images (ids 1..n) looking along +z, 0.1 apart along x, or with
// `arc_step_deg` on an arc round the points, that far apart as seen from them; each entry of
// `tracks` is a sparse point seen by those images.
Reconstruction ModelWithTracks(int num_images, const std::vector<std::vector<image_t>>& tracks,
                               double arc_step_deg = 0) {
  Reconstruction rec;
  rec.AddCamera(Camera::FromFocal(640, 480, 500));
  for (int i = 0; i < num_images; ++i) {
    Image image;
    image.image_id = i + 1;
    image.camera_id = rec.cameras().begin()->first;
    const double angle = arc_step_deg * i * std::numbers::pi / 180;
    const Eigen::Vector3d centre =
        arc_step_deg > 0 ? Eigen::Vector3d(10 * std::sin(angle), 0, 10 - 10 * std::cos(angle))
                         : Eigen::Vector3d(0.1 * i, 0, 0);
    image.cam_from_world = Rigid3d(Eigen::Matrix3d::Identity(), -centre);
    image.registered = true;
    rec.AddImage(image);
  }
  for (size_t k = 0; k < tracks.size(); ++k) {
    std::vector<TrackElement> track;
    for (const image_t id : tracks[k]) {
      Image& image = rec.image(id);
      track.push_back({id, static_cast<point2D_t>(image.points2D.size())});
      image.points2D.push_back({Eigen::Vector2d(320, 240)});
    }
    rec.AddPoint3D(Eigen::Vector3d(0.01 * k, 0, 10), track);
  }
  return rec;
}

std::vector<image_t> Range(image_t first, image_t last) {
  std::vector<image_t> ids;
  for (image_t id = first; id <= last; ++id) ids.push_back(id);
  return ids;
}

// `num_images` images, of which 1..12 see the same 50 points and the others none.
Reconstruction TwelveViewsOfOneSurface(int num_images = 12) {
  return ModelWithTracks(num_images, std::vector<std::vector<image_t>>(50, Range(1, 12)));
}

TEST(SelectReferenceViews, ViewsThatSeeTheSameSurfaceAreDroppedUntilEachPointKeepsEnough) {
  // Twelve views of the same 50 points. The means tie, so the views are judged by id: 1 to 7
  // each still leave every point five other views and are dropped; then a point has five views
  // left, and each of those would leave it only four. Each point keeps min_other_views views.
  const Reconstruction rec = TwelveViewsOfOneSurface();
  ReferenceViewOptions options;
  options.min_other_views = 5;
  EXPECT_EQ(SelectReferenceViews(rec, Range(1, 12), options, 3), Range(8, 12));
  // With two others asked, the points still keep the three views a fused point needs.
  options.min_other_views = 2;
  EXPECT_EQ(SelectReferenceViews(rec, Range(1, 12), options, 3), Range(10, 12));
  EXPECT_EQ(SelectReferenceViews(rec, Range(1, 12), options, 2), Range(11, 12));
}

TEST(SelectReferenceViews, TheViewsThatAloneReachASurfaceKeepTheirDepthMaps) {
  // Twelve views of 100 common points. Views 1, 2 and 3 also see 10 points of a side that only
  // they see; views 4 to 12 each see 10 points with their next view, which lowers their mean
  // track below that of 1, 2 and 3, so these are judged first. For each of 1, 2 and 3, 91 % of
  // its points have five other views, but without it the side's points would have two depth-map
  // views, fewer than a fused point needs: they stay.
  std::vector<std::vector<image_t>> tracks(100, Range(1, 12));
  for (int k = 0; k < 10; ++k) tracks.push_back({1, 2, 3});
  for (image_t view = 4; view <= 12; ++view)
    for (int k = 0; k < 10; ++k) tracks.push_back({view, view == 12 ? 4 : view + 1});
  const Reconstruction rec = ModelWithTracks(12, tracks);
  const auto kept_side_views = [&](const ReferenceViewOptions& options) {
    const std::vector<image_t> kept = SelectReferenceViews(rec, Range(1, 12), options, 3);
    return std::count_if(kept.begin(), kept.end(), [](image_t id) { return id <= 3; });
  };
  ReferenceViewOptions options;
  EXPECT_EQ(kept_side_views(options), 3);
  EXPECT_LT(SelectReferenceViews(rec, Range(1, 12), options, 3).size(), 12u);  // others go
  // Without the constraint they go, and the side with them.
  options.max_uncovered_fraction = 1.0;
  EXPECT_EQ(kept_side_views(options), 0);
}

TEST(SelectReferenceViews, OnlyViewsFromNearlyTheSamePlaceRepeatEachOther) {
  // Twelve views of the same 50 points on an arc, 5 degrees apart as the points see them. Within
  // 20 degrees a view has at most eight others; within 10 degrees at most four, fewer than five:
  // none is redundant. At any angle, as the twelve views along a line above.
  const Reconstruction rec =
      ModelWithTracks(12, std::vector<std::vector<image_t>>(50, Range(1, 12)), 5.0);
  ReferenceViewOptions options;
  options.max_view_angle_deg = 180;
  EXPECT_EQ(SelectReferenceViews(rec, Range(1, 12), options, 3).size(), 5u);
  options.max_view_angle_deg = 20;
  const size_t within_20 = SelectReferenceViews(rec, Range(1, 12), options, 3).size();
  EXPECT_GT(within_20, 5u);
  EXPECT_LT(within_20, 12u);
  options.max_view_angle_deg = 10;
  EXPECT_EQ(SelectReferenceViews(rec, Range(1, 12), options, 3), Range(1, 12));
}

TEST(SelectReferenceViews, EveryViewOfAFewPhotosPerSurfaceKeepsItsDepthMap) {
  // Eleven views along a facade, each point seen by three neighbours (the tracks of the shared
  // sets are about 3 long): no point has five other views.
  std::vector<std::vector<image_t>> tracks;
  for (image_t first = 1; first + 2 <= 11; ++first)
    for (int k = 0; k < 40; ++k) tracks.push_back({first, first + 1, first + 2});
  const Reconstruction rec = ModelWithTracks(11, tracks);
  EXPECT_EQ(SelectReferenceViews(rec, Range(1, 11), ReferenceViewOptions{}, 3), Range(1, 11));
}

TEST(SelectReferenceViews, AViewIsRedundantOnlyWhenEnoughOfItsPointsAreSeenElsewhere) {
  // Eight views see 100 common points. Views 1 and 2 also see 30 points that only they see
  // (view 1: 77 % of its points have five other views); views 3..8 each see 60 points with one
  // neighbour (62.5 %). 1 and 2 have the longest mean tracks and are judged first.
  std::vector<std::vector<image_t>> tracks(100, Range(1, 8));
  for (int k = 0; k < 30; ++k) tracks.push_back({1, 2});
  for (image_t first : {3, 5, 7})
    for (int k = 0; k < 60; ++k) tracks.push_back({first, first + 1});
  const Reconstruction rec = ModelWithTracks(8, tracks);
  ReferenceViewOptions options;
  EXPECT_EQ(SelectReferenceViews(rec, Range(1, 8), options, 3), Range(1, 8));
  // At 70 %, 1 goes, and then 2 (its 30 points are not counted covered, but 77 % still are):
  // what they alone saw is lost, which is why the default asks for more.
  options.redundant_fraction = 0.7;
  EXPECT_EQ(SelectReferenceViews(rec, Range(1, 8), options, 3), Range(3, 8));
}

TEST(SelectReferenceViews, OnlyTheCandidatesCountAndTheirOrderIsKept) {
  // Twelve views see the points, but only the candidates count as depth-map views: of six, one
  // can go; a second would leave the points four others.
  const Reconstruction rec = TwelveViewsOfOneSurface();
  const std::vector<image_t> candidates = {12, 3, 7, 5, 1, 9};
  EXPECT_EQ(SelectReferenceViews(rec, candidates, ReferenceViewOptions{}, 3),
            (std::vector<image_t>{12, 3, 7, 5, 9}));  // 1, judged first, goes
}

TEST(SelectReferenceViews, NoneIsRedundantAtFractionZero) {
  const Reconstruction rec = TwelveViewsOfOneSurface();
  ReferenceViewOptions options;
  options.redundant_fraction = 0;
  EXPECT_EQ(SelectReferenceViews(rec, Range(1, 12), options, 3), Range(1, 12));
}

TEST(SelectReferenceViews, AViewWithoutSparsePointsIsKept) {
  const Reconstruction rec = TwelveViewsOfOneSurface(13);
  const std::vector<image_t> kept =
      SelectReferenceViews(rec, Range(1, 13), ReferenceViewOptions{}, 3);
  EXPECT_EQ(kept.back(), 13u);
  EXPECT_EQ(kept.size(), 6u);
}

}  // namespace
}  // namespace varsfm
