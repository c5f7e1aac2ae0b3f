// Multi-view stereo on many views of one surface (dense/reference_views.h): the redundant views
// get no depth map, and the cloud still covers what every depth map would have covered.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <unordered_set>
#include <vector>

#include "dense/rendered_scene_truth.h"
#include "varsfm/dense/densify.h"
#include "varsfm/dense/reference_views.h"
#include "varsfm/synthetic/rendered_scene.h"

namespace varsfm {
namespace {

using testing::PlaneDistance;

// The voxel of side `size` that holds `p`.
int64_t VoxelKey(const Eigen::Vector3d& p, double size) {
  const Eigen::Vector3d v = (p / size).array().floor();
  return (static_cast<int64_t>(v.x()) + (1 << 20)) << 42 |
         (static_cast<int64_t>(v.y()) + (1 << 20)) << 21 |
         (static_cast<int64_t>(v.z()) + (1 << 20));
}

TEST(MultiViewStereo, RedundantViewsGetNoDepthMapAndTheCloudStillCoversTheSurface) {
  // Sixteen views 2 degrees apart: every sparse point is seen by most of them.
  RenderedSceneOptions options;
  options.num_images = 16;
  options.width = 160;
  options.height = 120;
  options.focal_start = 128;  // the default 640 at 800 px, scaled to 160 px
  options.arc_degrees = 30;
  const RenderedScene scene = RenderSyntheticScene(options);
  const Reconstruction rec = SparseModelFromRenderedScene(scene);
  const auto load = [&](image_t id) { return scene.images[id - 1]; };

  DenseReconstructionOptions dense;
  dense.method = DenseMethod::kPatchMatch;
  dense.mvs.patchmatch.num_iterations = 3;
  DensifyStats all_stats, stats;
  dense.mvs.references.redundant_fraction = 0;  // every view gets a depth map
  const PointCloud all = Densify(rec, load, dense, &all_stats);
  dense.mvs.references = {};
  const PointCloud cloud = Densify(rec, load, dense, &stats);

  EXPECT_EQ(all_stats.mvs.num_views, 16u);
  EXPECT_EQ(all_stats.mvs.num_redundant_views, 0u);
  EXPECT_EQ(stats.mvs.num_views + stats.mvs.num_redundant_views, 16u);
  EXPECT_GE(stats.mvs.num_redundant_views, 6u);
  ASSERT_GT(cloud.points.size(), 5000u);
  EXPECT_LT(cloud.points.size(), all.points.size());

  // As accurate as every depth map's cloud (measured: 5 depth maps, a median distance to the
  // surfaces of 0.0100 against 0.0127 with all 16, and 97.7 % of the full cloud near a point).
  const auto median_distance = [&](const PointCloud& c) {
    std::vector<double> distances;
    for (const Eigen::Vector3d& x : c.points) {
      Eigen::Vector3d normal;
      distances.push_back(PlaneDistance(scene.surface, x, &normal));
    }
    std::nth_element(distances.begin(), distances.begin() + distances.size() / 2, distances.end());
    return distances[distances.size() / 2];
  };
  const double all_median = median_distance(all), median = median_distance(cloud);
  EXPECT_LT(median, 1.1 * all_median);

  // As complete: nearly every point of the full cloud has a point of the reduced one in its
  // voxel of two pixel footprints or a neighbouring one.
  const double voxel = 0.08;
  std::unordered_set<int64_t> covered;
  for (const Eigen::Vector3d& p : cloud.points) covered.insert(VoxelKey(p, voxel));
  size_t near = 0;
  for (const Eigen::Vector3d& p : all.points) {
    bool found = false;
    for (int dx = -1; dx <= 1 && !found; ++dx)
      for (int dy = -1; dy <= 1 && !found; ++dy)
        for (int dz = -1; dz <= 1 && !found; ++dz)
          found = covered.count(VoxelKey(p + voxel * Eigen::Vector3d(dx, dy, dz), voxel)) > 0;
    near += found;
  }
  EXPECT_GT(static_cast<double>(near) / all.points.size(), 0.95);
}

TEST(SelectReferenceViews, TheRenderedScenesViewsKeepTheirDepthMaps) {
  // The scene of issue 18's geometric check (bench/surface_fscore: twelve views along a 50-degree
  // arc, complete tracks, 800 x 600). Counting the other views at any angle, the arc's middle
  // views went as redundant and the surfaces they alone saw face-on with them (F-score 0.966 ->
  // 0.886; bench/results/2026-12-07-s35-reference-coverage.md).
  const RenderedScene scene = RenderSyntheticScene(RenderedSceneOptions{});
  const Reconstruction rec = SparseModelFromRenderedScene(scene);
  std::vector<image_t> views;
  for (const image_t id : rec.RegisteredImageIds()) views.push_back(id);
  ASSERT_EQ(views.size(), 12u);
  EXPECT_GE(SelectReferenceViews(rec, views, ReferenceViewOptions{}, 3).size(), 11u);
  ReferenceViewOptions any_angle;
  any_angle.max_view_angle_deg = 180;
  any_angle.max_uncovered_fraction = 1;
  EXPECT_LE(SelectReferenceViews(rec, views, any_angle, 3).size(), 6u);
}

}  // namespace
}  // namespace varsfm
