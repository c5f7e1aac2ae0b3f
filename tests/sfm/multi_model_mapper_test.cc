#include "varsfm/sfm/multi_model_mapper.h"

#include <gtest/gtest.h>

#include <set>

#include "sfm/mapper_input.h"
#include "varsfm/eval/alignment.h"
#include "varsfm/synthetic/synthetic_scene.h"

namespace varsfm {
namespace {

using testing::AddScene;
using testing::MakeInput;
using testing::MapperInput;

// Two unrelated scenes (different points, cameras and zoom), noise-free so that each model
// must recover its scene's truth exactly (up to a similarity).
SyntheticOptions LargeScene() {
  SyntheticOptions o;
  o.num_images = 10;
  o.num_points = 1200;
  o.focal_start = 800;
  o.focal_end = 1200;
  o.arc_degrees = 70;
  o.look_at_jitter = 0.6;
  o.seed = 11;
  return o;
}

SyntheticOptions SmallScene() {
  SyntheticOptions o;
  o.num_images = 7;
  o.num_points = 1000;
  o.focal_start = o.focal_end = 1000;
  o.arc_degrees = 90;
  o.look_at_jitter = 0.5;
  o.seed = 23;
  return o;
}

// The model's registered images are exactly `ids` and its cameras are the scene's: focal
// lengths and camera centres (after a similarity alignment) to 1e-4.
void ExpectRecoversScene(const Reconstruction& rec, const SyntheticScene& scene,
                         const std::vector<image_t>& ids) {
  const std::vector<image_t> registered = rec.RegisteredImageIds();
  EXPECT_EQ(std::set<image_t>(registered.begin(), registered.end()),
            std::set<image_t>(ids.begin(), ids.end()));
  EXPECT_LT(rec.RmsReprojectionError(), 1e-3);
  std::vector<Eigen::Vector3d> estimated, truth;
  for (int i = 0; i < scene.NumImages(); ++i) {
    if (!rec.ExistsImage(ids[i]) || !rec.image(ids[i]).registered) continue;
    EXPECT_NEAR(rec.CameraOf(ids[i]).focal() / scene.cameras[i].focal(), 1.0, 1e-4)
        << "image " << ids[i];
    estimated.push_back(rec.image(ids[i]).Center());
    truth.push_back(scene.poses[i].Center());
  }
  ASSERT_GE(estimated.size(), 3u);
  const AlignmentResult alignment = AlignSimilarity(estimated, truth);
  ASSERT_TRUE(alignment.success);
  for (size_t i = 0; i < estimated.size(); ++i)
    EXPECT_LT((alignment.sim * estimated[i] - truth[i]).norm(), 1e-4 * 5.0) << "image " << i;
}

// Two unconnected groups of images, their ids interleaved, and one image that matches nothing:
// one model of each group, the larger first, and the lone image in none with its reason.
TEST(MultiModelMapper, UnconnectedScenesGiveOneModelEachLargestFirst) {
  const SyntheticScene large = GenerateSyntheticScene(LargeScene());
  const SyntheticScene small = GenerateSyntheticScene(SmallScene());
  std::vector<image_t> large_ids, small_ids;
  for (int i = 0; i < large.NumImages(); ++i) large_ids.push_back(2 * i + 2);
  for (int i = 0; i < small.NumImages(); ++i) small_ids.push_back(2 * i + 1);
  MapperInput in;
  AddScene(large, large_ids, "large", &in);
  AddScene(small, small_ids, "small", &in);
  const image_t lone = 100;
  Image image = in.reconstruction.image(large_ids[0]);
  image.image_id = lone;
  image.name = "lone";
  in.reconstruction.AddImage(image);
  in.graph.AddImage(lone, image.points2D.size());

  const MultiModelResult result = ReconstructAllModels(in.reconstruction, in.graph, {}, {});
  ASSERT_EQ(result.models.size(), 2u) << result.message;
  // The disparity criterion starts from the small scene's wider pairs; the larger model, built
  // second, comes first.
  EXPECT_EQ(result.models[0].build_order, 1u);
  EXPECT_EQ(result.models[0].summary.num_registered, large_ids.size());
  EXPECT_EQ(result.models[1].summary.num_registered, small_ids.size());
  ExpectRecoversScene(result.models[0].reconstruction, large, large_ids);
  ExpectRecoversScene(result.models[1].reconstruction, small, small_ids);
  ASSERT_EQ(result.unmodelled.size(), 1u);
  EXPECT_EQ(result.unmodelled[0].image_id, lone);
  EXPECT_NE(result.unmodelled[0].reason.find("no verified matches"), std::string::npos)
      << result.unmodelled[0].reason;
}

// A connected scene: one model, the single-model mapper's bit for bit.
TEST(MultiModelMapper, ConnectedSceneGivesTheSingleModelMappersModel) {
  const SyntheticScene scene = GenerateSyntheticScene(LargeScene());
  MapperInput in = MakeInput(scene);
  const MultiModelResult result = ReconstructAllModels(in.reconstruction, in.graph, {}, {});
  ASSERT_EQ(result.models.size(), 1u);
  EXPECT_TRUE(result.unmodelled.empty());
  ASSERT_TRUE(IncrementalMapper(in.graph, {}, {}).Reconstruct(&in.reconstruction).success);
  const Reconstruction& a = in.reconstruction;
  const Reconstruction& b = result.models[0].reconstruction;
  ASSERT_EQ(a.images().size(), b.images().size());
  ASSERT_EQ(a.points3D().size(), b.points3D().size());
  for (const auto& [id, image] : a.images()) {
    const Image& other = b.image(id);
    EXPECT_EQ(image.registered, other.registered) << id;
    EXPECT_EQ(image.cam_from_world.translation, other.cam_from_world.translation) << id;
    EXPECT_EQ(image.cam_from_world.rotation.coeffs(), other.cam_from_world.rotation.coeffs()) << id;
    EXPECT_EQ(a.camera(image.camera_id).params, b.camera(other.camera_id).params) << id;
  }
  for (const auto& [id, point] : a.points3D()) EXPECT_EQ(point.xyz, b.point3D(id).xyz) << id;
}

}  // namespace
}  // namespace varsfm
