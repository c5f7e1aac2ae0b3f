#include "varsfm/camera/image_size.h"

#include <algorithm>
#include <cmath>

namespace varsfm {

ScaledSize SizeWithin(const Camera& camera, int max_size) {
  ScaledSize size;
  size.scale = std::min(1.0, static_cast<double>(max_size) /
                                 static_cast<double>(std::max(camera.width, camera.height)));
  size.width = std::max(1, static_cast<int>(std::lround(camera.width * size.scale)));
  size.height = std::max(1, static_cast<int>(std::lround(camera.height * size.scale)));
  return size;
}

}  // namespace varsfm
