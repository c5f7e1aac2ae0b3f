// Exposure gains and seam levelling on two photos of a plane taken at different exposures: each
// photo textures the half of the plane it sees nearer, so a seam crosses the middle. Without
// levelling the rendering jumps there by the exposure difference; with it the colour runs on.
#include <gtest/gtest.h>

#include "plane_scene.h"
#include "varsfm/texture/render.h"
#include "varsfm/texture/texture_mapping.h"

namespace varsfm {
namespace {

struct TwoExposures {
  TriangleMesh mesh = testing::PlaneMesh();
  std::vector<PosedCamera> views = {testing::PlaneView({-0.9, 0, -2.5}, {0, 0, 0}),
                                    testing::PlaneView({0.9, 0, -2.5}, {0, 0, 0})};
  std::vector<cv::Mat> photos = {testing::PhotographPlane(views[0], 1.0),
                                 testing::PhotographPlane(views[1], 0.6)};
};

// The largest colour step between horizontally adjacent rendered pixels in the middle of the
// plane (rows and columns well inside it), seen from straight in front.
double LargestStep(const TexturedMesh& textured) {
  const PosedCamera front = testing::PlaneView({0, 0, -2.5}, {0, 0, 0});
  const Rendering r = RenderTexturedMesh(textured, front.camera, front.cam_from_world);
  double largest = 0;
  for (int y = 60; y < 140; ++y) {
    for (int x = 60; x < 140; ++x) {
      if (!r.mask.at<uchar>(y, x) || !r.mask.at<uchar>(y, x + 1)) continue;
      const cv::Vec3b a = r.image.at<cv::Vec3b>(y, x), b = r.image.at<cv::Vec3b>(y, x + 1);
      for (int k = 0; k < 3; ++k) largest = std::max(largest, std::abs(a[k] - b[k]) * 1.0);
    }
  }
  return largest;
}

TEST(Levelling, RemovesTheSeamBetweenTwoExposures) {
  const TwoExposures scene;
  const auto load = [&](size_t v) { return scene.photos[v]; };
  const ViewSelection selection =
      SelectViews(scene.mesh.vertices, scene.mesh.faces, scene.views, load);
  size_t left = 0;
  for (const int label : selection.labels) left += label == 0;
  ASSERT_GT(left, scene.mesh.faces.size() / 4) << "both photos must texture part of the plane";
  ASSERT_LT(left, 3 * scene.mesh.faces.size() / 4);
  // Gains: equal brightness after them (0.6 x gain 1 = 1 x gain 0), geometric mean 1.
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(selection.gains[1][k] * 0.6, selection.gains[0][k], 0.02) << k;
    EXPECT_NEAR(selection.gains[0][k] * selection.gains[1][k], 1.0, 0.02) << k;
  }

  TextureMappingOptions off;
  off.selection.exposure.enabled = false;
  off.levelling.enabled = false;
  off.seams.enabled = false;
  // The pattern changes by under 3 grey levels a pixel; the seam by 0.4 x 90-140.
  const double unlevelled = LargestStep(TextureMesh(scene.mesh, scene.views, load, off));
  EXPECT_GT(unlevelled, 30);

  // Levelling alone (additive, per vertex, fading a few edges from the seam) closes most of a
  // multiplicative gap (measured: 64 -> 19) ...
  TextureMappingOptions levelling_only;
  levelling_only.selection.exposure.enabled = false;
  levelling_only.levelling.max_seam_difference = 1000;  // the gap is all exposure here
  levelling_only.seams.enabled = false;
  EXPECT_LT(LargestStep(TextureMesh(scene.mesh, scene.views, load, levelling_only)),
            unlevelled / 2);
  // ... and with the gains first nothing is left but the pattern's own steps.
  EXPECT_LT(LargestStep(TextureMesh(scene.mesh, scene.views, load)), 6);
  // The local blending alone (seam_blending.h) also meets halfway at the seam, spreading the
  // gap over its strip in steps of a few grey levels (measured: 64 -> 6 with 6 texels a side).
  TextureMappingOptions blending_only = off;
  blending_only.seams.enabled = true;
  EXPECT_LT(LargestStep(TextureMesh(scene.mesh, scene.views, load, blending_only)), unlevelled / 4);
}

}  // namespace
}  // namespace varsfm
