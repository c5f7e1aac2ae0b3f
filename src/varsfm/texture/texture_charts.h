#pragma once
// Charts: connected faces textured from the same photo, and the photo's texels each needs in
// the atlas -- those its faces cover plus a gutter around them, so that bilinear lookups (and
// the first mip-map levels of viewers) at a chart's edge read the photo, not a neighbouring
// chart or the background. Only these texels are packed (atlas.h); the rest of a chart's
// bounding box is left to other charts.
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "varsfm/geometry/rasterizer.h"

namespace varsfm {

struct Chart {
  int view = -1;
  std::vector<int> faces;
  cv::Rect source;  // the chart's box in its photo, pixels (may reach outside the photo)
  cv::Mat mask;     // CV_8UC1 over `source`: 255 on the texels the atlas keeps
};

// Connected components of edge-adjacent faces with the same (valid) label; `neighbours` as
// FaceNeighbours (face_adjacency.h).
std::vector<Chart> GrowCharts(const std::vector<int>& labels,
                              const std::vector<std::array<int, 3>>& neighbours);

// Cuts a chart into the pieces that fall in the squares of a grid of `tile` photo pixels (each
// face goes with its centroid). Texels are the photo's own, with a gutter of the photo's pixels
// around every piece, so a cut shows nowhere in a rendering; but the pieces are compact where a
// whole chart is a long strip or a ring whose box would hold other charts' empty room, and
// compact shapes pack densely. `pixels`: the vertices projected into the chart's view (full
// resolution).
std::vector<Chart> CutChart(const Chart& chart, const std::vector<Eigen::Vector3i>& faces,
                            const std::vector<ProjectedVertex>& pixels, int tile);

// Sets a chart's source box and mask: the texels its faces' projections touch, grown by `gutter`
// texels (a square, as bilinear lookups reach one texel along x and y). `pixels` as for
// CutChart; `photo_size`: its view's. The box may reach outside the photo by at most a quarter of
// its size (the part of a face beyond that samples the box's edge). Returns the texels inside
// the chart's faces.
double SetChartMask(const std::vector<Eigen::Vector3i>& faces,
                    const std::vector<ProjectedVertex>& pixels, cv::Size photo_size, int gutter,
                    Chart* chart);

}  // namespace varsfm
