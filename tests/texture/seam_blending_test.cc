// Local seam blending on a synthetic two-exposure seam, where the Poisson solution is known
// exactly: two flat charts whose colours differ meet at a straight seam; each must move half the
// gap at the seam and fade linearly (the harmonic function of a straight strip) to its own colour
// `strip_width` texels away, so both read the same colour on the seam.
#include <gtest/gtest.h>

#include "varsfm/texture/face_adjacency.h"
#include "varsfm/texture/seam_blending.h"

namespace varsfm {
namespace {

constexpr int kWidth = 80, kHeight = 32;

// A unit square cut into chart A (faces 0, 1: left) and chart B (faces 2, 3: right) sharing the
// edge of vertices 1 and 4. In the atlas A's faces span x in [0, 32], B's x in [40, 72], both
// y in [0, 32]; A holds texels x < 34 (2 of gutter past the seam), B texels x >= 38.
struct TwoCharts {
  TexturedMesh mesh;
  std::vector<cv::Mat> owner;
  std::vector<int> chart_of_face = {0, 0, 1, 1};
};

TwoCharts MakeTwoCharts(const cv::Vec3b& a, const cv::Vec3b& b) {
  TwoCharts t;
  t.mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}};
  t.mesh.faces = {{0, 1, 4}, {0, 4, 3}, {1, 2, 5}, {1, 5, 4}};
  const auto uv = [](float x, float y) { return Eigen::Vector2f(x / kWidth, y / kHeight); };
  // Texcoords 0-3: A's corners of vertices 0, 1, 4, 3; 4-7: B's of vertices 1, 2, 5, 4.
  t.mesh.texcoords = {uv(0, 0),  uv(32, 0), uv(32, 32), uv(0, 32),
                      uv(40, 0), uv(72, 0), uv(72, 32), uv(40, 32)};
  t.mesh.face_texcoords = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}};
  t.mesh.face_page = {0, 0, 0, 0};
  cv::Mat page(kHeight, kWidth, CV_8UC3, cv::Scalar::all(0));
  cv::Mat owner(kHeight, kWidth, CV_32SC1, cv::Scalar::all(-1));
  page(cv::Rect(0, 0, 34, kHeight)).setTo(cv::Scalar(a[0], a[1], a[2]));
  owner(cv::Rect(0, 0, 34, kHeight)).setTo(0);
  page(cv::Rect(38, 0, 36, kHeight)).setTo(cv::Scalar(b[0], b[1], b[2]));
  owner(cv::Rect(38, 0, 36, kHeight)).setTo(1);
  t.mesh.pages = {page};
  t.owner = {owner};
  return t;
}

TEST(SeamBlending, TwoExposuresMeetHalfwayAndFadeLinearly) {
  const cv::Vec3b a(60, 90, 120), b(100, 70, 160);
  TwoCharts t = MakeTwoCharts(a, b);
  const cv::Mat before = t.mesh.pages[0].clone();
  SeamBlendingOptions options;
  options.strip_width = 8;
  BlendSeams(FaceNeighbours(t.mesh.faces), {0, 0, 1, 1}, t.chart_of_face, t.owner, options,
             &t.mesh);
  const cv::Mat& page = t.mesh.pages[0];
  const cv::Vec3f half_gap = 0.5f * (cv::Vec3f(b) - cv::Vec3f(a));
  // Texel centres at distance d from the seam: the seam texels (d = 0.5) move by the half gap,
  // the texels at d >= 8.5 not at all, and those between linearly: by (8.5 - d) / 8 of it.
  const auto fade = [](double d) { return std::clamp((8.5 - d) / 8, 0.0, 1.0); };
  constexpr double kRounding = 0.5 + 1e-6;  // to 8 bits
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < 32; ++x) {  // A, up to the seam at x = 32
      const double d = 32 - (x + 0.5);
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(page.at<cv::Vec3b>(y, x)[c], a[c] + fade(d) * half_gap[c], kRounding)
            << "A at x " << x << " y " << y;
    }
    for (int x = 40; x < 74; ++x) {  // B, from the seam at x = 40
      const double d = x + 0.5 - 40;
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(page.at<cv::Vec3b>(y, x)[c], b[c] - fade(d) * half_gap[c], kRounding)
            << "B at x " << x << " y " << y;
    }
    // The gutters past the seam, which bilinear lookups on the seam read, carry the seam colour.
    for (const int x : {32, 33})
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(page.at<cv::Vec3b>(y, x)[c], a[c] + half_gap[c], kRounding);
    for (const int x : {38, 39})
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(page.at<cv::Vec3b>(y, x)[c], b[c] - half_gap[c], kRounding);
    // Texels of no chart are left alone.
    for (int x = 34; x < 38; ++x) EXPECT_EQ(page.at<cv::Vec3b>(y, x), before.at<cv::Vec3b>(y, x));
  }
}

TEST(SeamBlending, PiecesOfOnePhotoAreNoSeam) {
  // The same two charts as pieces of one photo (one label): nothing to blend.
  TwoCharts t = MakeTwoCharts({60, 90, 120}, {100, 70, 160});
  const cv::Mat before = t.mesh.pages[0].clone();
  BlendSeams(FaceNeighbours(t.mesh.faces), {3, 3, 3, 3}, t.chart_of_face, t.owner, {}, &t.mesh);
  EXPECT_EQ(cv::norm(t.mesh.pages[0], before, cv::NORM_INF), 0);
}

TEST(SeamBlending, DisabledChangesNothing) {
  TwoCharts t = MakeTwoCharts({60, 90, 120}, {100, 70, 160});
  const cv::Mat before = t.mesh.pages[0].clone();
  SeamBlendingOptions options;
  options.enabled = false;
  BlendSeams(FaceNeighbours(t.mesh.faces), {0, 0, 1, 1}, t.chart_of_face, t.owner, options,
             &t.mesh);
  EXPECT_EQ(cv::norm(t.mesh.pages[0], before, cv::NORM_INF), 0);
}

}  // namespace
}  // namespace varsfm
