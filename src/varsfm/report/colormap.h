#pragma once
// The colour scale that ties the report's pictures together: a camera's frustum in the 3D view
// and its marker in the focal-length plot get the same colour for the same focal length.
#include <string>

namespace varsfm {

// A perceptually ordered scale from dark purple (t = 0) through teal to yellow (t = 1), linear
// between five samples of matplotlib's viridis; t is clamped to [0, 1]. Returns "#rrggbb".
std::string ViridisHex(double t);

}  // namespace varsfm
