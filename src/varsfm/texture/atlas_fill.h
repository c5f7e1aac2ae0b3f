#pragma once
// Bleeding chart colours into the empty atlas around them. Viewers sample textures through
// mip-maps (glTF sampler LINEAR_MIPMAP_LINEAR): at a coarse level a texel averages a large block
// of the atlas, and a chart's edge would mix with the black background, drawing dark seams
// along chart borders when the model is seen from afar. Giving the background near the charts
// the colour of the nearest chart texel keeps those averages right.
#include <opencv2/core.hpp>

namespace varsfm {

// `page`: BGR 8-bit atlas; `filled`: 8-bit mask, non-zero on texels that hold chart colour.
// Empty texels within `rings` texels of a filled one take that nearest texel's colour (one
// distance transform with nearest-pixel labels, linear in the atlas size).
void BleedAtlasBackground(cv::Mat* page, const cv::Mat& filled, int rings);

}  // namespace varsfm
