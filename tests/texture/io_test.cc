// Textured models on disk: OBJ + MTL + PNG read back as written, the GLB parses as glTF 2.0 with
// its texture embedded, and bad input (missing or empty mesh, a model without registered
// images) is a varsfm::Error.
#include <gtest/gtest.h>

#include <fstream>

#include <tiny_gltf.h>

#include "support/test_data.h"
#include "synthetic_mesh.h"
#include "varsfm/image/png_codec.h"
#include "varsfm/io/mesh_ply.h"
#include "varsfm/io/obj_io.h"
#include "varsfm/texture/gltf_writer.h"
#include "varsfm/texture/model_texture.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

using testing::TempDir;

// A small textured mesh: two pages, random texture coordinates.
TexturedMesh SmallTexturedMesh() {
  TexturedMesh mesh;
  const TriangleMesh grid = testing::SyntheticSceneMesh(1.0);
  mesh.vertices = grid.vertices;
  mesh.faces = grid.faces;
  cv::RNG rng(3);
  for (size_t f = 0; f < mesh.faces.size(); ++f) {
    Eigen::Vector3i tc;
    for (int k = 0; k < 3; ++k) {
      tc[k] = static_cast<int>(mesh.texcoords.size());
      mesh.texcoords.emplace_back(rng.uniform(0.f, 1.f), rng.uniform(0.f, 1.f));
    }
    mesh.face_texcoords.push_back(tc);
    mesh.face_page.push_back(static_cast<int>(f % 2));
  }
  for (int p = 0; p < 2; ++p) {
    cv::Mat page(32, 48, CV_8UC3);
    rng.fill(page, cv::RNG::UNIFORM, 0, 256);
    mesh.pages.push_back(page);
  }
  return mesh;
}

TEST(TexturedObj, RoundTripsAndReferencesExistingFiles) {
  TempDir tmp("obj");
  const TexturedMesh mesh = SmallTexturedMesh();
  WriteTexturedObj(tmp.path() / "textured", mesh, "model");
  // The MTL's textures are files next to it.
  std::ifstream mtl(tmp.path() / "textured" / "model.mtl");
  std::string line;
  int textures = 0;
  while (std::getline(mtl, line)) {
    if (line.rfind("map_Kd ", 0) != 0) continue;
    ++textures;
    EXPECT_TRUE(std::filesystem::is_regular_file(tmp.path() / "textured" / line.substr(7))) << line;
  }
  EXPECT_EQ(textures, 2);

  const TexturedMesh back = ReadTexturedObj(tmp.path() / "textured" / "model.obj");
  ASSERT_EQ(back.faces.size(), mesh.faces.size());
  ASSERT_EQ(back.vertices.size(), mesh.vertices.size());
  ASSERT_EQ(back.pages.size(), 2u);
  // Faces come back grouped by page: match them by their vertices. Same multiset of (face, page)
  // pairs and identical texture coordinates per corner.
  std::map<std::array<int, 3>, std::pair<int, Eigen::Vector2f>> written;
  for (size_t f = 0; f < mesh.faces.size(); ++f)
    written[{mesh.faces[f][0], mesh.faces[f][1], mesh.faces[f][2]}] = {
        mesh.face_page[f], mesh.texcoords[mesh.face_texcoords[f][0]]};
  for (size_t f = 0; f < back.faces.size(); ++f) {
    const auto it = written.find({back.faces[f][0], back.faces[f][1], back.faces[f][2]});
    ASSERT_NE(it, written.end());
    EXPECT_EQ(cv::norm(back.pages[back.face_page[f]], mesh.pages[it->second.first], cv::NORM_INF),
              0.0);
    EXPECT_LT((back.texcoords[back.face_texcoords[f][0]] - it->second.second).norm(), 1e-6);
  }
  for (size_t v = 0; v < mesh.vertices.size(); ++v)
    EXPECT_LT((back.vertices[v] - mesh.vertices[v]).norm(), 1e-6);
}

// Accepts the embedded PNGs without decoding them (the test checks structure, not pixels).
bool KeepImageBytes(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                    const unsigned char*, int, void*) {
  return true;
}

TEST(Glb, IsParseableGltfWithEmbeddedTextures) {
  TempDir tmp("glb");
  const TexturedMesh mesh = SmallTexturedMesh();
  const auto file = tmp.path() / "model.glb";
  WriteGlb(file, mesh);
  // GLB header: magic "glTF", version 2, total length = file size.
  std::ifstream in(file, std::ios::binary);
  uint32_t header[3];
  in.read(reinterpret_cast<char*>(header), sizeof(header));
  EXPECT_EQ(header[0], 0x46546C67u);
  EXPECT_EQ(header[1], 2u);
  EXPECT_EQ(header[2], std::filesystem::file_size(file));

  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(KeepImageBytes, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, file.string())) << err;
  ASSERT_EQ(model.meshes.size(), 1u);
  ASSERT_EQ(model.nodes.size(), 1u);
  EXPECT_EQ(model.nodes[0].rotation, std::vector<double>({1, 0, 0, 0}));  // y down -> y up
  ASSERT_EQ(model.meshes[0].primitives.size(), 2u);
  ASSERT_EQ(model.images.size(), 2u);
  size_t triangles = 0;
  for (const tinygltf::Primitive& p : model.meshes[0].primitives) {
    triangles += model.accessors[p.indices].count / 3;
    EXPECT_EQ(p.attributes.count("TEXCOORD_0"), 1u);
    const int texture = model.materials[p.material].pbrMetallicRoughness.baseColorTexture.index;
    ASSERT_GE(texture, 0);
    const tinygltf::Image& image = model.images[model.textures[texture].source];
    EXPECT_EQ(image.mimeType, "image/png");
    // The embedded bytes decode to the page.
    const tinygltf::BufferView& view = model.bufferViews[image.bufferView];
    const std::vector<uchar> png(
        model.buffers[view.buffer].data.begin() + view.byteOffset,
        model.buffers[view.buffer].data.begin() + view.byteOffset + view.byteLength);
    const cv::Mat decoded = DecodePng(png.data(), png.size(), ColorMode::kColor);
    EXPECT_EQ(decoded.size(), mesh.pages[0].size());
  }
  EXPECT_EQ(triangles, mesh.faces.size());
}

TEST(MeshReader, ReadsWhatTheMeshStageWrites) {
  TempDir tmp("mesh_reader");
  TriangleMesh mesh = testing::SyntheticSceneMesh(1.0);
  mesh.colors.assign(mesh.vertices.size(), Eigen::Matrix<uint8_t, 3, 1>(10, 20, 30));
  WriteMeshPly(tmp.path() / "mesh.ply", mesh);
  const TriangleMesh back = ReadMeshPly(tmp.path() / "mesh.ply");
  EXPECT_EQ(back.faces, mesh.faces);
  ASSERT_EQ(back.vertices.size(), mesh.vertices.size());
  EXPECT_EQ(back.colors.size(), mesh.colors.size());
  EXPECT_EQ(back.colors[0], mesh.colors[0]);
}

TEST(MeshReader, MissingOrEmptyMeshIsAnError) {
  TempDir tmp("mesh_reader_bad");
  EXPECT_THROW(ReadMeshPly(tmp.path() / "none.ply"), Error);
  TriangleMesh empty;
  empty.vertices.emplace_back(0, 0, 0);
  WriteMeshPly(tmp.path() / "empty.ply", empty);
  EXPECT_THROW(ReadMeshPly(tmp.path() / "empty.ply"), Error);
  std::ofstream(tmp.path() / "junk.ply") << "not a ply\n";
  EXPECT_THROW(ReadMeshPly(tmp.path() / "junk.ply"), Error);
  EXPECT_THROW(ReadTexturedObj(tmp.path() / "none.obj"), Error);
}

TEST(ModelTexture, ModelWithoutRegisteredImagesIsAnError) {
  Reconstruction rec;
  Camera camera = Camera::FromFocal(100, 80, 90);
  camera.camera_id = 1;
  rec.AddCamera(camera);
  Image image;
  image.image_id = 1;
  image.camera_id = 1;
  image.name = "a.png";
  rec.AddImage(image);  // not registered
  EXPECT_THROW(TextureFromModel(testing::SyntheticSceneMesh(1.0), rec, "/nonexistent"), Error);
  rec.RegisterImage(1);  // registered, but its photo is missing
  EXPECT_THROW(TextureFromModel(testing::SyntheticSceneMesh(1.0), rec, "/nonexistent"), Error);
}

}  // namespace
}  // namespace varsfm

namespace varsfm {
namespace {

// What viewers and engines rely on, checked by the Khronos reference validator.
TEST(Glb, KhronosValidatorReportsNoErrors) {
  TempDir tmp("glb_validator");
  const auto file = tmp.path() / "model.glb";
  WriteGlb(file, SmallTexturedMesh());
  int code = -1;
  std::string output, why;
  if (!testing::ValidateGltf(file, &code, &output, &why)) GTEST_SKIP() << why << "; skipping";
  EXPECT_EQ(code, 0) << output;
  EXPECT_NE(output.find(": 0 errors"), std::string::npos) << output;
}

}  // namespace
}  // namespace varsfm
