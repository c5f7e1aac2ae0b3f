// Texturing the rendered synthetic scene (exact cameras, exact geometry) and rendering it back:
// the rendering matches the photos where the mesh covers them, with and without lens distortion.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "synthetic_mesh.h"
#include "varsfm/synthetic/rendered_scene.h"
#include "varsfm/texture/render.h"
#include "varsfm/texture/texture_mapping.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

struct Textured {
  RenderedScene scene;
  TexturedMesh mesh;
  TextureMappingStats stats;
};

// Textures the scene mesh from the first `num_used` of the rendered images.
Textured TextureScene(double k1, int num_used, const TextureMappingOptions& options = {}) {
  RenderedSceneOptions o;
  o.num_images = 6;
  o.width = 400;
  o.height = 300;
  o.focal_start = 320;
  o.k1 = k1;
  o.supersampling = 1;
  Textured t;
  t.scene = RenderSyntheticScene(o);
  std::vector<PosedCamera> views;
  for (int i = 0; i < num_used; ++i) views.push_back({t.scene.cameras[i], t.scene.poses[i]});
  t.mesh = TextureMesh(
      testing::SyntheticSceneMesh(), views, [&](size_t v) { return t.scene.images[v]; }, options,
      &t.stats);
  return t;
}

PhotometricScore RenderAndCompare(const Textured& t, int image) {
  const Rendering r = RenderTexturedMesh(t.mesh, t.scene.cameras[image], t.scene.poses[image]);
  const PhotometricScore s = ComparePhotometric(r, t.scene.images[image]);
  return s;
}

// Measured: 27.2, 28.6, 29.9 dB (image 0 loses a little at the image border, where faces cut by
// it are drawn with the border pixels repeated); coverage 0.90 (the rest is background), 1, 1.
TEST(Texture, RenderingMatchesThePhotosItWasTexturedFrom) {
  const Textured t = TextureScene(0.0, 6);
  // Much of the room is out of every view (floor under and behind the cameras, most of the
  // left wall, the wall and floor behind the boxes): measured 61 % of the faces textured.
  EXPECT_GT(t.stats.num_textured_faces, t.stats.num_faces / 2);
  EXPECT_LT(t.stats.num_charts, t.stats.num_faces / 20) << "smoothing should group faces";
  for (const int image : {0, 3, 5}) {
    const PhotometricScore s = RenderAndCompare(t, image);
    EXPECT_GT(s.coverage, 0.85) << image;
    EXPECT_GT(s.psnr_db, 25.0) << image;
  }
}

// The exposure gains' pairs, the levelling's channels and the seams' bands are computed in
// parallel, each into its own place: the textured model is the same bits at any thread count.
TEST(Texture, SameModelWhateverTheThreadCount) {
  TextureMappingOptions options;
  options.levelling.direct_max_unknowns = 0;  // the conjugate gradients, channel by channel
  const auto textured_with = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    return TextureScene(0.0, 6, options).mesh;
  };
  const TexturedMesh one = textured_with(1), four = textured_with(4);
  ASSERT_EQ(one.pages.size(), four.pages.size());
  ASSERT_FALSE(one.pages.empty());
  for (size_t p = 0; p < one.pages.size(); ++p) {
    ASSERT_EQ(one.pages[p].size(), four.pages[p].size());
    EXPECT_EQ(cv::norm(one.pages[p], four.pages[p], cv::NORM_INF), 0) << p;
  }
  EXPECT_EQ(one.texcoords, four.texcoords);
  EXPECT_EQ(one.face_texcoords, four.face_texcoords);
}

// From copies of half the photos' size: a quarter of the atlas, and the rendering at full size
// still close to the photos (a little softer).
TEST(Texture, MaxImageSizeTexturesFromSmallerCopies) {
  const Textured full = TextureScene(0.1, 6);
  TextureMappingOptions options;
  options.max_image_size = 200;  // the photos are 400 x 300
  const Textured half = TextureScene(0.1, 6, options);
  EXPECT_LT(half.stats.atlas_pixels, full.stats.atlas_pixels / 3);
  // Faces at the edge of visibility are judged on the smaller copies: measured 7879 of 7949.
  EXPECT_GT(half.stats.num_textured_faces, 0.97 * full.stats.num_textured_faces);
  for (const int image : {0, 3}) {
    const PhotometricScore s = RenderAndCompare(half, image);
    EXPECT_GT(s.coverage, 0.85) << image;
    EXPECT_GT(s.psnr_db, 22.0) << image;
  }
  options.max_image_size = 10;
  EXPECT_ANY_THROW(options.Check());
}

TEST(Texture, HeldOutViewIsClose) {
  // Textured from images 0-4 only; image 5 (the most zoomed) is rendered by resampling others.
  const Textured t = TextureScene(0.0, 5);
  const PhotometricScore s = RenderAndCompare(t, 5);
  EXPECT_GT(s.coverage, 0.85);
  EXPECT_GT(s.psnr_db, 21.0);  // measured 23.2 dB
}

// k1 = -0.08: barrel distortion of ~5 % at the image corners. Measured 27.2 and 30.0 dB.
TEST(Texture, RadialDistortionIsModelled) {
  const Textured t = TextureScene(-0.08, 6);
  for (const int image : {0, 5}) {
    const PhotometricScore s = RenderAndCompare(t, image);
    EXPECT_GT(s.coverage, 0.85) << image;
    EXPECT_GT(s.psnr_db, 25.0) << image;
  }
}

// Two small views of the synthetic scene, for the tests that need photos but not their detail.
RenderedScene SmallTwoViewScene() {
  RenderedSceneOptions o;
  o.num_images = 2;
  o.width = 160;
  o.height = 120;
  o.focal_start = 128;
  o.supersampling = 1;
  return RenderSyntheticScene(o);
}

TEST(Texture, UnseenFacesKeepTheirVertexColour) {
  const RenderedScene scene = SmallTwoViewScene();
  TriangleMesh mesh = testing::SyntheticSceneMesh(0.5);
  mesh.colors.assign(mesh.vertices.size(), Eigen::Matrix<uint8_t, 3, 1>(200, 40, 10));  // RGB
  // The only view looks away from the scene, so no face is textured from a photo.
  const PosedCamera away{scene.cameras[0], LookAt({0, 0, 0}, {0, 0, -5})};
  TextureMappingStats stats;
  TextureMappingOptions options;
  options.min_mean_coverage = 0;  // the coverage check would stop it (next test)
  const TexturedMesh textured = TextureMesh(
      mesh, {away}, [&](size_t) { return scene.images[0]; }, options, &stats);
  EXPECT_EQ(stats.num_textured_faces, 0u);
  EXPECT_EQ(stats.mean_coverage, 0);
  const Rendering r = RenderTexturedMesh(textured, scene.cameras[1], scene.poses[1]);
  ASSERT_GT(cv::countNonZero(r.mask), 0);
  for (int y = 0; y < r.image.rows; ++y)
    for (int x = 0; x < r.image.cols; ++x)
      if (r.mask.at<uchar>(y, x)) ASSERT_EQ(r.image.at<cv::Vec3b>(y, x), cv::Vec3b(10, 40, 200));
}

TEST(Texture, AMeshThePhotosDoNotShowIsAnError) {
  const RenderedScene scene = SmallTwoViewScene();
  const TriangleMesh mesh = testing::SyntheticSceneMesh(0.5);
  const auto load = [&](size_t v) { return scene.images[v]; };
  // From the scene's own cameras the mesh fills much of each photo.
  TextureMappingStats stats;
  TextureMesh(mesh, {{scene.cameras[0], scene.poses[0]}, {scene.cameras[1], scene.poses[1]}}, load,
              {}, &stats);
  EXPECT_GT(stats.mean_coverage, 0.2);
  // A view looking away sees none of it: one line naming the coverage.
  const PosedCamera away{scene.cameras[0], LookAt({0, 0, 0}, {0, 0, -5})};
  try {
    TextureMesh(mesh, {away}, load);
    ADD_FAILURE() << "no error for a mesh no photo shows";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("covers 0.00 % of the photos"), std::string::npos) << message;
  }
}

TEST(Texture, EmptyMeshOrNoViewsIsAnError) {
  const TriangleMesh mesh = testing::SyntheticSceneMesh(0.5);
  const auto load = [](size_t) { return cv::Mat(); };
  EXPECT_THROW(TextureMesh(TriangleMesh(), {PosedCamera{Camera::FromFocal(10, 10, 10), {}}}, load),
               Error);
  EXPECT_THROW(TextureMesh(mesh, {}, load), Error);
}

}  // namespace
}  // namespace varsfm
