#include "varsfm/texture/atlas.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "varsfm/util/error.h"

namespace varsfm {

AtlasLayout PackRectangles(const std::vector<AtlasRect>& rects, int max_page_size) {
  double total_area = 0;
  int widest = 1, tallest = 1;
  for (const AtlasRect& r : rects) {
    if (r.width < 0 || r.height < 0) Fail("atlas: rectangle of negative size");
    total_area += static_cast<double>(r.width) * r.height;
    widest = std::max(widest, r.width);
    tallest = std::max(tallest, r.height);
  }
  // Shelves waste some room; aim a little wider than the ideal square.
  const int page_width = std::max(
      widest, std::min(max_page_size, static_cast<int>(std::ceil(std::sqrt(total_area) * 1.1))));
  const int max_height = std::max(tallest, max_page_size);

  std::vector<size_t> order(rects.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return rects[a].height > rects[b].height; });

  AtlasLayout layout;
  layout.placements.resize(rects.size());
  layout.pages.push_back({page_width, 0});
  int x = 0, shelf_y = 0, shelf_height = 0;
  for (const size_t i : order) {
    const AtlasRect& r = rects[i];
    if (x + r.width > page_width) {  // row full: next shelf
      shelf_y += shelf_height;
      x = 0;
      shelf_height = 0;
    }
    if (shelf_y + r.height > max_height) {  // page full: next page
      layout.pages.push_back({page_width, 0});
      x = 0;
      shelf_y = 0;
      shelf_height = 0;
    }
    layout.placements[i] = {static_cast<int>(layout.pages.size()) - 1, x, shelf_y};
    x += r.width;
    shelf_height = std::max(shelf_height, r.height);
    AtlasRect& page = layout.pages.back();
    page.height = std::max(page.height, shelf_y + r.height);
  }
  for (AtlasRect& page : layout.pages) page.height = std::max(page.height, 1);
  return layout;
}

}  // namespace varsfm
