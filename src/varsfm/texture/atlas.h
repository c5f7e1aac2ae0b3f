#pragma once
// Packing charts into texture atlas pages by their shapes, not their bounding boxes. A chart is
// a mask: the texels it needs (its faces' texels and a gutter around them). The charts of a
// reconstructed mesh are irregular strips and blobs whose bounding boxes are mostly empty, so
// packing boxes (shelves, Coffman et al. 1980) left three quarters of the atlas empty. Here each
// mask is described per column by its first and last texel (its top and bottom profiles), and
// charts are dropped, largest first, onto a skyline of per-column heights at the position and
// orientation (as is, or turned by 90 degrees) where they come to rest highest up, ties going to
// the position that leaves the least room unusable under them -- the skyline heuristic of
// Jylanki ("A thousand ways to pack the bin", 2010) with the chart's own profile in place of
// its rectangle, so that charts interlock.
#include <vector>

#include <opencv2/core.hpp>

namespace varsfm {

struct AtlasPlacement {
  int page = 0;
  int x = 0;  // top-left corner of the (possibly turned) mask's box in the page, pixels
  int y = 0;
  // Turned by 90 degrees clockwise (cv::ROTATE_90_CLOCKWISE): a box of width w and height h
  // takes h columns and w rows, and the mask's point (u, v) lands at (h - v, u).
  bool rotated = false;
};

struct AtlasPage {
  int width = 0;
  int height = 0;
};

struct AtlasLayout {
  std::vector<AtlasPlacement> placements;  // one per input mask, in input order
  std::vector<AtlasPage> pages;            // size of each page
};

// `masks`: CV_8UC1, non-zero on the texels a chart needs. Pages are as wide as about the square
// root of the masks' total area (at least the narrowest side of the largest box), at most
// max_page_size wide and high unless one chart is larger. Non-zero texels of two charts never
// share a page texel. Throws varsfm::Error for a mask that is empty or not CV_8UC1.
AtlasLayout PackCharts(const std::vector<cv::Mat>& masks, int max_page_size = 8192);

// The mask as placed: turned when the placement says so.
cv::Mat PlacedMask(const cv::Mat& mask, const AtlasPlacement& placement);

}  // namespace varsfm
