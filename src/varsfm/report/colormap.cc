#include "varsfm/report/colormap.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/format.h>

namespace varsfm {

std::string ViridisHex(double t) {
  // viridis at 0, 1/4, 1/2, 3/4, 1.
  static constexpr std::array<std::array<double, 3>, 5> kStops = {{{0x44, 0x01, 0x54},
                                                                   {0x3b, 0x52, 0x8b},
                                                                   {0x21, 0x91, 0x8c},
                                                                   {0x5e, 0xc9, 0x62},
                                                                   {0xfd, 0xe7, 0x25}}};
  if (!std::isfinite(t)) t = 0;
  t = std::clamp(t, 0.0, 1.0) * (kStops.size() - 1);
  const size_t i = std::min(static_cast<size_t>(t), kStops.size() - 2);
  const double w = t - static_cast<double>(i);
  std::array<int, 3> rgb{};
  for (int c = 0; c < 3; ++c)
    rgb[c] = static_cast<int>(std::lround((1 - w) * kStops[i][c] + w * kStops[i + 1][c]));
  return fmt::format("#{:02x}{:02x}{:02x}", rgb[0], rgb[1], rgb[2]);
}

}  // namespace varsfm
