#pragma once
// An image's size capped on its longer side: what a stage that works on smaller copies of the
// photos (depth maps, visibility rasters, texture copies) scales them by.
#include "varsfm/camera/camera.h"

namespace varsfm {

struct ScaledSize {
  double scale = 1;  // never above 1: an image is never enlarged
  int width = 0;     // each side scaled and rounded, at least 1
  int height = 0;
};

// `camera`'s image scaled to at most `max_size` pixels on its longer side.
ScaledSize SizeWithin(const Camera& camera, int max_size);

}  // namespace varsfm
