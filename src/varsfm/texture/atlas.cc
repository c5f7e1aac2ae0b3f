#include "varsfm/texture/atlas.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "varsfm/util/error.h"

namespace varsfm {
namespace {

// A mask's first texel (top) and one past its last (bottom) in every column; an empty column
// has top = height and bottom = 0, so it constrains nothing.
struct Profile {
  int width = 0;
  int height = 0;
  std::vector<int> top;
  std::vector<int> bottom;
};

Profile ColumnProfile(const cv::Mat& mask) {
  Profile p;
  p.width = mask.cols;
  p.height = mask.rows;
  p.top.assign(mask.cols, mask.rows);
  p.bottom.assign(mask.cols, 0);
  for (int y = 0; y < mask.rows; ++y) {
    const uchar* row = mask.ptr<uchar>(y);
    for (int x = 0; x < mask.cols; ++x) {
      if (!row[x]) continue;
      p.top[x] = std::min(p.top[x], y);
      p.bottom[x] = y + 1;
    }
  }
  return p;
}

struct Spot {
  int x = 0;
  int y = std::numeric_limits<int>::max();
  long long waste = std::numeric_limits<long long>::max();
};

// The highest resting place of `p` on `sky` (per column, the first free row; the page is
// `sky.size()` wide): for each x, the mask rests where one of its columns touches the skyline.
Spot BestSpot(const std::vector<int>& sky, const Profile& p) {
  Spot best;
  const int page_width = static_cast<int>(sky.size());
  for (int x = 0; x + p.width <= page_width; ++x) {
    int y = 0;
    for (int c = 0; c < p.width && y <= best.y; ++c)
      if (p.bottom[c] > 0) y = std::max(y, sky[x + c] - p.top[c]);
    if (y > best.y) continue;
    long long waste = 0;
    for (int c = 0; c < p.width; ++c)
      if (p.bottom[c] > 0) waste += y + p.top[c] - sky[x + c];
    if (y < best.y || waste < best.waste) best = {x, y, waste};
  }
  return best;
}

}  // namespace

cv::Mat PlacedMask(const cv::Mat& mask, const AtlasPlacement& placement) {
  if (!placement.rotated) return mask;
  cv::Mat turned;
  cv::rotate(mask, turned, cv::ROTATE_90_CLOCKWISE);
  return turned;
}

AtlasLayout PackCharts(const std::vector<cv::Mat>& masks, int max_page_size) {
  std::vector<std::array<Profile, 2>> profiles(masks.size());
  std::vector<double> area(masks.size());
  double total_area = 0;
  int narrowest_fit = 1, longest = 1;
  for (size_t i = 0; i < masks.size(); ++i) {
    const cv::Mat& m = masks[i];
    if (m.empty() || m.type() != CV_8UC1) Fail("atlas: a chart's mask is empty or not 8-bit");
    area[i] = cv::countNonZero(m);
    if (area[i] == 0) Fail("atlas: a chart's mask has no texel");
    total_area += area[i];
    narrowest_fit = std::max(narrowest_fit, std::min(m.cols, m.rows));
    longest = std::max(longest, std::max(m.cols, m.rows));
    profiles[i][0] = ColumnProfile(m);
    profiles[i][1] = ColumnProfile(PlacedMask(m, {0, 0, 0, true}));
  }
  // Interlocking profiles still leave some room under overhangs; aim a little wider than the
  // ideal square.
  const int page_width =
      std::max(narrowest_fit,
               std::min(max_page_size, static_cast<int>(std::ceil(std::sqrt(total_area) * 1.1))));
  const int max_height = std::max(longest, max_page_size);

  // Large charts first (by their longer side, then area): small ones fill what is left.
  std::vector<size_t> order(masks.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    const int la = std::max(masks[a].cols, masks[a].rows);
    const int lb = std::max(masks[b].cols, masks[b].rows);
    return la != lb ? la > lb : area[a] > area[b];
  });

  AtlasLayout layout;
  layout.placements.resize(masks.size());
  layout.pages.push_back({page_width, 0});
  std::vector<int> sky(page_width, 0);
  for (const size_t i : order) {
    int chosen = -1;
    Spot spot;
    for (int turn = 0; turn < 2; ++turn) {
      const Profile& p = profiles[i][turn];
      if (p.width > page_width) continue;
      const Spot s = BestSpot(sky, p);
      // Compare by where the chart's box ends: the higher up, the more of the page is left.
      const int end = s.y + p.height;
      const int chosen_end = chosen < 0 ? 0 : spot.y + profiles[i][chosen].height;
      if (chosen < 0 || end < chosen_end || (end == chosen_end && s.waste < spot.waste)) {
        chosen = turn;
        spot = s;
      }
    }
    const Profile* p = &profiles[i][chosen];
    if (spot.y + p->height > max_height) {  // page full: the next one
      layout.pages.push_back({page_width, 0});
      std::fill(sky.begin(), sky.end(), 0);
      chosen = profiles[i][0].width <= page_width ? 0 : 1;
      p = &profiles[i][chosen];
      spot = BestSpot(sky, *p);
    }
    layout.placements[i] = {static_cast<int>(layout.pages.size()) - 1, spot.x, spot.y, chosen == 1};
    for (int c = 0; c < p->width; ++c)
      if (p->bottom[c] > 0) sky[spot.x + c] = spot.y + p->bottom[c];
    AtlasPage& page = layout.pages.back();
    page.height = std::max(page.height, spot.y + p->height);
  }
  for (AtlasPage& page : layout.pages) page.height = std::max(page.height, 1);
  return layout;
}

}  // namespace varsfm
