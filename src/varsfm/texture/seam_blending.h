#pragma once
// Local blending at seams (Waechter, Moehrle & Goesele, "Let there be color!", ECCV 2014,
// sec. 4.2), after the global levelling of colour_levelling.h, which closes the gap between two
// charts only on average along their seam: what is left -- detail misregistered by a pixel, a
// highlight in one photo -- still shows as a step. Waechter et al. solve a Poisson equation on a
// strip of each chart along its seams, with the guidance field the chart's own gradients, the
// seam texels fixed to the mean of the two charts' colours there and the strip's inner edge
// fixed to the chart's colour. With the chart's own gradients as guidance, the change to the
// chart is harmonic: it is the solution d of Laplace(d) = 0 on the strip, with d = (other chart
// - this chart) / 2 on the seam and d = 0 at `strip_width` texels from it (a straight seam with
// a constant gap fades linearly). Texels of other charts and the atlas background take no part:
// the chart's edges away from seams are free (zero normal derivative). Solved per atlas page,
// by conjugate gradients (Eigen's, Jacobi-preconditioned), three right-hand sides.
#include <array>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "varsfm/scene/textured_mesh.h"

namespace varsfm {

struct SeamBlendingOptions {
  bool enabled = true;
  // Texels from a seam at which a chart keeps its own colour.
  int strip_width = 6;
  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

// `labels`: per face, the photo that textures it (-1: none); `chart_of_face`: per face, the
// chart (atlas piece) that holds it (-1: none, e.g. the unseen faces' palette); `owner`: per
// atlas page, CV_32SC1, the chart each texel belongs to (-1: none). A seam is an edge between
// faces of two photos (`neighbours`: face_adjacency.h); an edge between two pieces of one photo
// is none (both hold the same pixels), and the strip does not reach across it. Changes the
// texels of mesh->pages within strip_width of a seam.
void BlendSeams(const std::vector<std::array<int, 3>>& neighbours, const std::vector<int>& labels,
                const std::vector<int>& chart_of_face, const std::vector<cv::Mat>& owner,
                const SeamBlendingOptions& options, TexturedMesh* mesh);

}  // namespace varsfm
