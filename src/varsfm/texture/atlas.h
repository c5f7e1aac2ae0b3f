#pragma once
// Packing chart rectangles into texture atlas pages by shelves ("next-fit decreasing height",
// Coffman et al. 1980, as surveyed by Jylanki, "A thousand ways to pack the bin", 2010): sort by
// height, fill rows left to right, start a new row when one is full and a new page when a page
// is. Simple, fast (n log n), and wastes little for the many small, similar charts of a mesh.
#include <vector>

namespace varsfm {

struct AtlasRect {
  int width = 0;
  int height = 0;
};

struct AtlasPlacement {
  int page = 0;
  int x = 0;  // top-left corner in the page, pixels
  int y = 0;
};

struct AtlasLayout {
  std::vector<AtlasPlacement> placements;  // one per input rectangle, in input order
  std::vector<AtlasRect> pages;            // size of each page
};

// Pages are square-ish: as wide as sqrt(total area) (at least the widest rectangle), at most
// max_page_size wide and high unless one rectangle is larger. Rectangles never overlap.
// Throws varsfm::Error for a rectangle with a negative size.
AtlasLayout PackRectangles(const std::vector<AtlasRect>& rects, int max_page_size = 8192);

}  // namespace varsfm
