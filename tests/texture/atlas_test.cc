// Packing charts by shape: every chart inside its page, no two charts on one texel, irregular
// charts interlocking, tall charts turned, and chart masks covering what bilinear lookups read.
#include <gtest/gtest.h>

#include <random>

#include <opencv2/imgproc.hpp>

#include "varsfm/texture/atlas.h"
#include "varsfm/texture/texture_charts.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

// Paints every placed mask into its page and fails on a texel painted twice; returns the texels
// painted per page.
std::vector<double> ExpectDisjoint(const std::vector<cv::Mat>& masks, const AtlasLayout& layout) {
  std::vector<cv::Mat> count;
  for (const AtlasPage& page : layout.pages)
    count.emplace_back(page.height, page.width, CV_8UC1, cv::Scalar::all(0));
  std::vector<double> painted(layout.pages.size(), 0);
  EXPECT_EQ(layout.placements.size(), masks.size());
  for (size_t i = 0; i < masks.size(); ++i) {
    const AtlasPlacement& p = layout.placements[i];
    EXPECT_GE(p.page, 0);
    EXPECT_LT(p.page, static_cast<int>(layout.pages.size()));
    const cv::Mat placed = PlacedMask(masks[i], p);
    EXPECT_GE(p.x, 0);
    EXPECT_GE(p.y, 0);
    EXPECT_LE(p.x + placed.cols, layout.pages[p.page].width);
    EXPECT_LE(p.y + placed.rows, layout.pages[p.page].height);
    cv::Mat region = count[p.page](cv::Rect(p.x, p.y, placed.cols, placed.rows));
    cv::add(region, cv::Scalar::all(1), region, placed);
    painted[p.page] += cv::countNonZero(placed);
  }
  for (const cv::Mat& c : count) {
    double most = 0;
    cv::minMaxLoc(c, nullptr, &most);
    EXPECT_LE(most, 1) << "two charts share a texel";
  }
  return painted;
}

// A filled triangle with corners chosen at random in a box of up to 120 x 120 texels: the
// irregular shapes of real charts, whose bounding boxes are half empty.
std::vector<cv::Mat> RandomTriangles(size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> size(2, 120);
  std::vector<cv::Mat> masks;
  for (size_t i = 0; i < n; ++i) {
    const int w = size(rng), h = size(rng);
    cv::Mat m(h, w, CV_8UC1, cv::Scalar::all(0));
    std::uniform_int_distribution<int> corner(0, 3);
    const std::vector<cv::Point> box = {{0, 0}, {w - 1, 0}, {w - 1, h - 1}, {0, h - 1}};
    const int skip = corner(rng);
    std::vector<cv::Point> tri;
    for (int k = 0; k < 4; ++k)
      if (k != skip) tri.push_back(box[k]);
    cv::fillConvexPoly(m, tri, cv::Scalar::all(255));
    masks.push_back(m);
  }
  return masks;
}

TEST(Atlas, TrianglesInterlockWithoutOverlap) {
  const std::vector<cv::Mat> masks = RandomTriangles(600, 7);
  double area = 0, boxes = 0;
  for (const cv::Mat& m : masks) {
    area += cv::countNonZero(m);
    boxes += m.total();
  }
  const AtlasLayout layout = PackCharts(masks);
  ASSERT_EQ(layout.pages.size(), 1u);
  ExpectDisjoint(masks, layout);
  const double page = static_cast<double>(layout.pages[0].width) * layout.pages[0].height;
  // Half of every box is empty: packing boxes could fill at most ~half the page with texels.
  EXPECT_GT(area / boxes, 0.49);
  EXPECT_LT(area / boxes, 0.56);
  EXPECT_GT(area / page, 0.6) << "triangles should interlock, using their boxes' empty halves";
}

TEST(Atlas, RectanglesFillThePage) {
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> size(1, 120);
  std::vector<cv::Mat> masks;
  double area = 0;
  for (int i = 0; i < 500; ++i) {
    masks.emplace_back(size(rng), size(rng), CV_8UC1, cv::Scalar::all(255));
    area += masks.back().total();
  }
  const AtlasLayout layout = PackCharts(masks);
  ASSERT_EQ(layout.pages.size(), 1u);
  ExpectDisjoint(masks, layout);
  const double page = static_cast<double>(layout.pages[0].width) * layout.pages[0].height;
  EXPECT_GT(area / page, 0.75);
}

TEST(Atlas, TallChartsAreTurned) {
  // A 60 x 60 square and three 10 x 60 bars: the page is 81 wide; two bars stand beside the
  // square, the third fits only lying on top of it (70 rows in all, 120 standing).
  std::vector<cv::Mat> masks(3, cv::Mat(60, 10, CV_8UC1, cv::Scalar::all(255)));
  masks.emplace_back(60, 60, CV_8UC1, cv::Scalar::all(255));
  const AtlasLayout layout = PackCharts(masks);
  ExpectDisjoint(masks, layout);
  ASSERT_EQ(layout.pages.size(), 1u);
  EXPECT_EQ(layout.pages[0].width, 81);
  EXPECT_EQ(layout.pages[0].height, 70);
  int turned = 0;
  for (size_t i = 0; i < 3; ++i) turned += layout.placements[i].rotated;
  EXPECT_EQ(turned, 1);
}

TEST(Atlas, PlacedMaskTurnsClockwise) {
  cv::Mat mask(2, 3, CV_8UC1, cv::Scalar::all(0));
  mask.at<uchar>(0, 2) = 255;  // top-right texel, centre (2.5, 0.5)
  const cv::Mat turned = PlacedMask(mask, {0, 0, 0, true});
  ASSERT_EQ(turned.rows, 3);
  ASSERT_EQ(turned.cols, 2);
  // (u, v) -> (h - v, u) = (1.5, 2.5): column 1, row 2.
  EXPECT_EQ(turned.at<uchar>(2, 1), 255);
  EXPECT_EQ(cv::countNonZero(turned), 1);
}

TEST(Atlas, OverflowStartsNewPages) {
  std::vector<cv::Mat> masks(50, cv::Mat(100, 100, CV_8UC1, cv::Scalar::all(255)));
  const AtlasLayout layout = PackCharts(masks, 256);
  EXPECT_GT(layout.pages.size(), 1u);
  ExpectDisjoint(masks, layout);
  for (const AtlasPage& page : layout.pages) {
    EXPECT_LE(page.width, 256);
    EXPECT_LE(page.height, 256);
  }
}

TEST(Atlas, EmptyMaskIsAnError) {
  EXPECT_THROW(PackCharts({cv::Mat(4, 4, CV_8UC1, cv::Scalar::all(0))}), Error);
  EXPECT_THROW(PackCharts({cv::Mat()}), Error);
}

TEST(ChartMask, CoversEveryTexelABilinearLookupInsideAFaceReads) {
  // Two faces of one chart in view 0; lookups anywhere inside them read 2 x 2 texels.
  const std::vector<Eigen::Vector3i> faces = {{0, 1, 2}, {0, 2, 3}};
  std::vector<std::vector<ProjectedVertex>> pixels(1);
  for (const Eigen::Vector2d& p : {Eigen::Vector2d(10.3, 12.7), Eigen::Vector2d(40.2, 15.1),
                                   Eigen::Vector2d(37.9, 44.6), Eigen::Vector2d(14.4, 30.2)})
    pixels[0].push_back({p, 1.0});
  for (const int gutter : {1, 2}) {
    std::vector<Chart> charts(1);
    charts[0].view = 0;
    charts[0].faces = {0, 1};
    const double face_texels = SetChartMask(faces, pixels[0], cv::Size(64, 64), gutter, &charts[0]);
    // The quadrilateral's area by the shoelace formula.
    EXPECT_NEAR(face_texels,
                0.5 * std::abs((40.2 - 10.3) * (44.6 - 12.7) - (37.9 - 10.3) * (15.1 - 12.7)) +
                    0.5 * std::abs((37.9 - 10.3) * (30.2 - 12.7) - (14.4 - 10.3) * (44.6 - 12.7)),
                1e-9);
    const Chart& chart = charts[0];
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> unit(0, 1);
    for (int i = 0; i < 2000; ++i) {
      const Eigen::Vector3i& face = faces[i % 2];
      double a = unit(rng), b = unit(rng);
      if (a + b > 1) a = 1 - a, b = 1 - b;
      const Eigen::Vector2d p = pixels[0][face[0]].pixel +
                                a * (pixels[0][face[1]].pixel - pixels[0][face[0]].pixel) +
                                b * (pixels[0][face[2]].pixel - pixels[0][face[0]].pixel);
      // Bilinear lookup: texels floor(p - 0.5) and the next along x and y.
      const int x0 = static_cast<int>(std::floor(p.x() - 0.5)) - chart.source.x;
      const int y0 = static_cast<int>(std::floor(p.y() - 0.5)) - chart.source.y;
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
          ASSERT_TRUE(cv::Rect(0, 0, chart.mask.cols, chart.mask.rows)
                          .contains(cv::Point(x0 + dx, y0 + dy)));
          ASSERT_EQ(chart.mask.at<uchar>(y0 + dy, x0 + dx), 255) << p.transpose();
        }
    }
    // Little more than the faces and their gutter: the quadrilateral's perimeter is ~110.
    EXPECT_LT(cv::countNonZero(chart.mask), face_texels + 110 * (gutter + 1.5) + 50);
  }
}

}  // namespace
}  // namespace varsfm
