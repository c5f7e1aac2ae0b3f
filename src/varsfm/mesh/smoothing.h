#pragma once
// Taubin's lambda|mu smoothing (Taubin, "A signal processing approach to fair surface design",
// SIGGRAPH 1995): alternating a shrinking Laplacian step (lambda > 0) and an inflating one
// (mu < -lambda) low-pass filters the vertex positions without the shrinkage of plain Laplacian
// smoothing. An interpolating surface (every vertex a dense point) carries the points' depth
// noise as bumps; a few passes remove it while keeping shapes larger than a few edges.
#include "varsfm/scene/triangle_mesh.h"

namespace varsfm {

// `iterations` lambda|mu pairs over the umbrella operator (mean of the edge neighbours).
// Deterministic; vertices without edges stay.
void TaubinSmooth(int iterations, TriangleMesh* mesh, double lambda = 0.5, double mu = -0.53);

}  // namespace varsfm
