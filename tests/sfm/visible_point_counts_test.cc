#include "varsfm/sfm/visible_point_counts.h"

#include <gtest/gtest.h>

#include <random>

namespace varsfm {
namespace {

// The score by its definition: the image's 2D points with a correspondence at a registered
// image's 2D point that has a 3D point.
size_t CountedFromScratch(const CorrespondenceGraph& graph, const Reconstruction& rec,
                          image_t image_id) {
  size_t visible = 0;
  for (point2D_t idx = 0; idx < graph.NumPoints2D(image_id); ++idx)
    for (const Correspondence& corr : graph.CorrespondencesOf(image_id, idx)) {
      const Image& other = rec.image(corr.image_id);
      if (other.registered && other.points2D[corr.point2D_idx].HasPoint3D()) {
        ++visible;
        break;
      }
    }
  return visible;
}

// `num_images` images of `num_points` 2D points each, declared in the graph and (unregistered,
// each with its own camera) in the model.
void AddImages(image_t num_images, point2D_t num_points, CorrespondenceGraph* graph,
               Reconstruction* rec) {
  for (image_t id = 1; id <= num_images; ++id) {
    graph->AddImage(id, num_points);
    Camera camera;
    camera.camera_id = id;
    rec->AddCamera(camera);
    Image image;
    image.image_id = id;
    image.camera_id = id;
    image.points2D.resize(num_points);
    rec->AddImage(image);
  }
}

// Random matches between 8 images of 30 points, and a model edited at random through every
// method that changes which 2D points have 3D points or which images are registered: the counts
// kept by the observer equal the counts from scratch after each edit.
TEST(VisiblePointCounts, FollowTheModelThroughEveryKindOfEdit) {
  constexpr image_t kImages = 8;
  constexpr point2D_t kPoints = 30;
  std::mt19937 rng(7);
  CorrespondenceGraph graph;
  Reconstruction rec;
  AddImages(kImages, kPoints, &graph, &rec);
  std::uniform_int_distribution<image_t> any_image(1, kImages);
  std::uniform_int_distribution<point2D_t> any_point(0, kPoints - 1);
  for (image_t a = 1; a <= kImages; ++a)
    for (image_t b = a + 1; b <= kImages; ++b) {
      FeatureMatches matches;
      for (int k = 0; k < 12; ++k) matches.push_back({any_point(rng), any_point(rng)});
      graph.AddImagePair(a, b, matches);
    }

  VisiblePointCounts counts(graph);
  rec.RegisterImage(1);
  rec.RegisterImage(2);
  rec.AddPoint3D(Eigen::Vector3d::Zero(), {{1, 0}, {2, 0}});  // before observing: recounted
  const ObservedReconstruction observed(&rec, &counts);
  std::uniform_int_distribution<int> any_edit(0, 6);
  size_t checks = 0, nonzero = 0;
  for (int step = 0; step < 400; ++step) {
    const image_t image_id = any_image(rng);
    const point2D_t idx = any_point(rng);
    const Point2D& p2 = rec.image(image_id).points2D[idx];
    switch (any_edit(rng)) {
      case 0: {  // a new point on two free 2D points
        const image_t other = image_id % kImages + 1;
        const point2D_t other_idx = any_point(rng);
        if (!p2.HasPoint3D() && !rec.image(other).points2D[other_idx].HasPoint3D())
          rec.AddPoint3D(Eigen::Vector3d::Zero(), {{image_id, idx}, {other, other_idx}});
        break;
      }
      case 1:  // one more observation of an existing point
        if (!p2.HasPoint3D() && !rec.points3D().empty())
          rec.AddObservation(rec.points3D().begin()->first, {image_id, idx});
        break;
      case 2:
        rec.DeleteObservation(image_id, idx);
        break;
      case 3:
        if (p2.HasPoint3D()) rec.DeletePoint3D(p2.point3D_id);
        break;
      case 4:
        if (rec.points3D().size() >= 2)
          rec.MergePoints3D(rec.points3D().begin()->first, rec.points3D().rbegin()->first);
        break;
      case 5:
        rec.RegisterImage(image_id);
        break;
      case 6:
        if (step % 5 == 0) rec.DeRegisterImage(image_id);
        break;
    }
    for (image_t id = 1; id <= kImages; ++id) {
      const size_t expected = CountedFromScratch(graph, rec, id);
      ASSERT_EQ(counts.VisiblePoints(id), expected) << "image " << id << " after step " << step;
      ++checks;
      nonzero += expected > 0;
    }
  }
  EXPECT_EQ(checks, 400u * kImages);
  EXPECT_GT(nonzero, checks / 4);  // the edits kept a good part of the images seeing points
}

TEST(VisiblePointCounts, ACopyOfAnObservedModelIsNotObserved) {
  CorrespondenceGraph graph;
  Reconstruction rec;
  AddImages(2, 2, &graph, &rec);
  graph.AddImagePair(1, 2, {{0, 0}, {1, 1}});
  VisiblePointCounts counts(graph);
  const ObservedReconstruction observed(&rec, &counts);
  rec.RegisterImage(1);
  Reconstruction copy = rec;
  copy.RegisterImage(2);
  copy.AddPoint3D(Eigen::Vector3d::Zero(), {{1, 0}, {2, 0}});
  EXPECT_EQ(counts.VisiblePoints(2), 0u);
  rec.RegisterImage(2);
  rec.AddPoint3D(Eigen::Vector3d::Zero(), {{1, 1}, {2, 1}});
  EXPECT_EQ(counts.VisiblePoints(1), 1u);
  EXPECT_EQ(counts.VisiblePoints(2), 1u);
}

}  // namespace
}  // namespace varsfm
