// The map stage on workspaces made from synthetic scenes: unconnected groups of images give one
// model each in OUT/sparse/0, 1, ... (largest first) and summary.json says which image is where.
#include "varsfm/pipeline/map.h"

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <set>

#include <fmt/format.h>

#include "support/test_data.h"
#include "varsfm/camera/colmap_models.h"
#include "varsfm/io/colmap_model.h"
#include "varsfm/io/database.h"
#include "varsfm/synthetic/synthetic_scene.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;

SyntheticOptions Group(int num_images, uint64_t seed) {
  SyntheticOptions o;
  o.num_images = num_images;
  o.num_points = 1000;
  o.focal_start = 900;
  o.focal_end = 1100;
  o.arc_degrees = 70;
  o.look_at_jitter = 0.6;
  o.noise_sigma = 0.3;
  o.seed = seed;
  return o;
}

// Writes the scene's images (named PREFIX0.png, ...) into the workspace with their keypoints,
// a camera each at the extraction's usual prior, and every pair's true correspondences as its
// verified matches. Returns the names.
std::vector<std::string> AddToWorkspace(const SyntheticScene& scene, const std::string& prefix,
                                        Database* db) {
  std::vector<std::string> names;
  std::vector<image_t> ids;
  for (int i = 0; i < scene.NumImages(); ++i) {
    const Camera& truth = scene.cameras[i];
    DbCamera camera;
    camera.model_id = kColmapSimpleRadial;
    camera.width = truth.width;
    camera.height = truth.height;
    camera.params = {1.2 * std::max(truth.width, truth.height), truth.width / 2.0,
                     truth.height / 2.0, 0.0};
    DbImage image;
    image.name = fmt::format("{}{}.png", prefix, i);
    image.camera_id = db->WriteCamera(camera);
    ids.push_back(db->WriteImage(image));
    names.push_back(image.name);
    FeatureKeypoints keypoints;
    for (const auto& obs : scene.observations[i])
      keypoints.emplace_back(static_cast<float>(obs.pixel.x()), static_cast<float>(obs.pixel.y()));
    db->WriteKeypoints(ids.back(), keypoints);
  }
  for (int i = 0; i < scene.NumImages(); ++i) {
    std::map<int, point2D_t> index_of_point;
    for (point2D_t k = 0; k < scene.observations[i].size(); ++k)
      index_of_point[scene.observations[i][k].point_id] = k;
    for (int j = i + 1; j < scene.NumImages(); ++j) {
      TwoViewGeometry geometry;
      geometry.config = TwoViewGeometry::kUncalibrated;
      for (point2D_t k = 0; k < scene.observations[j].size(); ++k) {
        const auto it = index_of_point.find(scene.observations[j][k].point_id);
        if (it != index_of_point.end()) geometry.inlier_matches.push_back({it->second, k});
      }
      db->WriteTwoViewGeometry(ids[i], ids[j], geometry);
    }
  }
  return names;
}

std::set<std::string> RegisteredNames(const fs::path& model) {
  const Reconstruction rec = ReadColmapModel(model);
  std::set<std::string> names;
  for (const image_t id : rec.RegisteredImageIds()) names.insert(rec.image(id).name);
  return names;
}

nlohmann::json ReadSummary(const fs::path& out) {
  return nlohmann::json::parse(std::ifstream(out / "summary.json"));
}

// Two unrelated scenes and a photo that matches nothing in one workspace: a model of each scene,
// the larger as model 0, and the photo in no model, with its reason. What an earlier run left in
// OUT/sparse (a single-model layout, a third model) goes.
TEST(MapStage, UnconnectedScenesGiveAModelEachLargestFirst) {
  testing::TempDir tmp("map_unconnected");
  std::vector<std::string> small, large, lone;
  {
    Database db(tmp.path() / "workspace.db");
    small = AddToWorkspace(GenerateSyntheticScene(Group(5, 3)), "small", &db);
    large = AddToWorkspace(GenerateSyntheticScene(Group(8, 5)), "large", &db);
    lone = AddToWorkspace(GenerateSyntheticScene(Group(1, 7)), "lone", &db);
  }
  const fs::path out = tmp.path() / "out";
  WriteColmapModel(Reconstruction{}, out / "sparse", {.binary = true});
  WriteColmapModel(Reconstruction{}, out / "sparse" / "2");

  MapOptions options;
  options.workspace = tmp.path() / "workspace.db";
  options.output = out;
  const MapSummary result = RunMapping(options);
  EXPECT_EQ(result.reconstruction.NumRegisteredImages(), large.size());
  EXPECT_EQ(result.num_images, small.size() + large.size() + 1);

  EXPECT_EQ(RegisteredNames(out / "sparse" / "0"),
            std::set<std::string>(large.begin(), large.end()));
  EXPECT_EQ(RegisteredNames(out / "sparse" / "1"),
            std::set<std::string>(small.begin(), small.end()));
  EXPECT_FALSE(fs::exists(out / "sparse" / "2"));
  EXPECT_FALSE(fs::exists(out / "sparse" / "cameras.bin"));
  EXPECT_EQ(RegisteredNames(out / "sparse"), RegisteredNames(out / "sparse" / "0"));

  const nlohmann::json summary = ReadSummary(out);
  EXPECT_EQ(summary["images_total"], small.size() + large.size() + 1);
  EXPECT_EQ(summary["images_registered"], large.size());
  ASSERT_EQ(summary["models"].size(), 2u);
  EXPECT_EQ(summary["models"][0]["path"], "sparse/0");
  EXPECT_EQ(summary["models"][0]["images"].get<std::vector<std::string>>(), large);
  EXPECT_EQ(summary["models"][1]["images"].get<std::vector<std::string>>(), small);
  ASSERT_EQ(summary["images_in_no_model"].size(), 1u);
  EXPECT_EQ(summary["images_in_no_model"][0]["name"], lone[0]);
  EXPECT_NE(summary["images_in_no_model"][0]["reason"].get<std::string>().find("no verified"),
            std::string::npos);
  for (const auto& image : summary["images"]) {
    const std::string name = image["name"];
    const nlohmann::json expected = name.starts_with("large")   ? nlohmann::json(0)
                                    : name.starts_with("small") ? nlohmann::json(1)
                                                                : nlohmann::json(nullptr);
    EXPECT_EQ(image["model"], expected) << name;
    EXPECT_EQ(image["registered"], name.starts_with("large")) << name;
  }
}

// One connected scene: exactly one model, and no second folder; summary.json counts the two-view
// points the filter after the final adjustment removed.
TEST(MapStage, ConnectedSceneGivesOneModel) {
  testing::TempDir tmp("map_connected");
  std::vector<std::string> names;
  {
    Database db(tmp.path() / "workspace.db");
    SyntheticScene scene = GenerateSyntheticScene(Group(8, 5));
    // 30 points seen by images 0 and 1 only, 2.5 px off in image 1 (across the epipolar lines
    // of the horizontal arc): two-view points that no third view contradicts.
    for (int i = 2; i < scene.NumImages(); ++i)
      std::erase_if(scene.observations[i], [](const auto& obs) { return obs.point_id < 30; });
    for (auto& obs : scene.observations[1])
      if (obs.point_id < 30) obs.pixel.y() += 2.5;
    names = AddToWorkspace(scene, "image", &db);
  }
  MapOptions options;
  options.workspace = tmp.path() / "workspace.db";
  options.output = tmp.path() / "out";
  RunMapping(options);
  EXPECT_EQ(RegisteredNames(options.output / "sparse" / "0"),
            std::set<std::string>(names.begin(), names.end()));
  EXPECT_FALSE(fs::exists(options.output / "sparse" / "1"));
  const nlohmann::json summary = ReadSummary(options.output);
  EXPECT_EQ(summary["models"].size(), 1u);
  EXPECT_TRUE(summary["images_in_no_model"].empty());
  // The two-view filter after the final adjustment says what it removed: the model without it
  // has exactly those points more (the runs are the same up to the filter).
  options.mapper.adjustment.final_two_view_filter_factor = 0;
  options.output = tmp.path() / "out_unfiltered";
  RunMapping(options);
  const nlohmann::json unfiltered = ReadSummary(options.output);
  const size_t removed = summary["two_view_points_removed"].get<size_t>();
  EXPECT_GE(removed, 20u);  // most of the 30 (a few may fall along an epipolar line)
  EXPECT_LE(removed, 40u);
  EXPECT_EQ(unfiltered["two_view_points_removed"].get<size_t>(), 0u);
  EXPECT_EQ(summary["points3D"].get<size_t>() + removed, unfiltered["points3D"].get<size_t>());
}

// A new model in a folder where an earlier run left the later stages' results: those were made
// from the old model, so they go (a failed densify would otherwise leave the old mesh and
// textured model beside the new cameras); what is not a stage's output stays.
TEST(MapStage, ResultsOfTheEarlierModelGo) {
  testing::TempDir tmp("map_stale");
  {
    Database db(tmp.path() / "workspace.db");
    AddToWorkspace(GenerateSyntheticScene(Group(6, 7)), "image", &db);
  }
  MapOptions options;
  options.workspace = tmp.path() / "workspace.db";
  options.output = tmp.path() / "out";
  const std::vector<fs::path> stale = {"dense.ply",  "dense.ply.vis", "dense_summary.json",
                                       "mesh.ply",   "model.glb",     "textured/model.obj",
                                       "report.html"};
  for (const fs::path& file : stale) {
    fs::create_directories((options.output / file).parent_path());
    std::ofstream(options.output / file) << "from an earlier model";
  }
  std::ofstream(options.output / "notes.txt") << "the user's";
  // The earlier model's summary: the folder is one varsfm wrote (output_folder.h).
  std::ofstream(options.output / "summary.json") << "{}";
  RunMapping(options);
  for (const fs::path& file : stale) EXPECT_FALSE(fs::exists(options.output / file)) << file;
  EXPECT_FALSE(fs::exists(options.output / "textured"));
  EXPECT_TRUE(fs::exists(options.output / "notes.txt"));
  EXPECT_TRUE(fs::exists(options.output / "sparse" / "0" / "images.bin"));
}

}  // namespace
}  // namespace varsfm
