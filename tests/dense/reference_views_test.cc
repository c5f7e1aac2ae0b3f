// Which views get a depth map (dense/reference_views.h), on hand-made sparse models whose tracks
// say which image sees which point.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "varsfm/dense/reference_views.h"

namespace varsfm {
namespace {

// `num_images` registered images (ids 1..n) looking along +z; each entry of `tracks` is a sparse
// point seen by those images.
Reconstruction ModelWithTracks(int num_images, const std::vector<std::vector<image_t>>& tracks) {
  Reconstruction rec;
  rec.AddCamera(Camera::FromFocal(640, 480, 500));
  for (int i = 0; i < num_images; ++i) {
    Image image;
    image.image_id = i + 1;
    image.camera_id = rec.cameras().begin()->first;
    image.cam_from_world = Rigid3d(Eigen::Matrix3d::Identity(), Eigen::Vector3d(-0.1 * i, 0, 0));
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
  EXPECT_EQ(SelectReferenceViews(rec, Range(1, 12), options), Range(8, 12));
  options.min_other_views = 2;
  EXPECT_EQ(SelectReferenceViews(rec, Range(1, 12), options), Range(11, 12));
}

TEST(SelectReferenceViews, EveryViewOfAFewPhotosPerSurfaceKeepsItsDepthMap) {
  // Eleven views along a facade, each point seen by three neighbours (the tracks of the shared
  // sets are about 3 long): no point has five other views.
  std::vector<std::vector<image_t>> tracks;
  for (image_t first = 1; first + 2 <= 11; ++first)
    for (int k = 0; k < 40; ++k) tracks.push_back({first, first + 1, first + 2});
  const Reconstruction rec = ModelWithTracks(11, tracks);
  EXPECT_EQ(SelectReferenceViews(rec, Range(1, 11), ReferenceViewOptions{}), Range(1, 11));
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
  EXPECT_EQ(SelectReferenceViews(rec, Range(1, 8), options), Range(1, 8));
  // At 70 %, 1 goes, and then 2 (its 30 points are not counted covered, but 77 % still are):
  // what they alone saw is lost, which is why the default asks for more.
  options.redundant_fraction = 0.7;
  EXPECT_EQ(SelectReferenceViews(rec, Range(1, 8), options), Range(3, 8));
}

TEST(SelectReferenceViews, OnlyTheCandidatesCountAndTheirOrderIsKept) {
  // Twelve views see the points, but only the candidates count as depth-map views: of six, one
  // can go; a second would leave the points four others.
  const Reconstruction rec = TwelveViewsOfOneSurface();
  const std::vector<image_t> candidates = {12, 3, 7, 5, 1, 9};
  EXPECT_EQ(SelectReferenceViews(rec, candidates, ReferenceViewOptions{}),
            (std::vector<image_t>{12, 3, 7, 5, 9}));  // 1, judged first, goes
}

TEST(SelectReferenceViews, NoneIsRedundantAtFractionZero) {
  const Reconstruction rec = TwelveViewsOfOneSurface();
  ReferenceViewOptions options;
  options.redundant_fraction = 0;
  EXPECT_EQ(SelectReferenceViews(rec, Range(1, 12), options), Range(1, 12));
}

TEST(SelectReferenceViews, AViewWithoutSparsePointsIsKept) {
  const Reconstruction rec = TwelveViewsOfOneSurface(13);
  const std::vector<image_t> kept = SelectReferenceViews(rec, Range(1, 13), ReferenceViewOptions{});
  EXPECT_EQ(kept.back(), 13u);
  EXPECT_EQ(kept.size(), 6u);
}

}  // namespace
}  // namespace varsfm
