#pragma once
// The exact truth of a rendered scene (rendered_scene.h) in the forms tests and benchmarks of
// the dense and surface stages consume: its surface as a triangle mesh, ray casts against it,
// and a sparse model with the true cameras whose points lie exactly on the surface.
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "varsfm/scene/triangle_mesh.h"
#include "varsfm/scene/reconstruction.h"
#include "varsfm/synthetic/rendered_scene.h"

namespace varsfm {

// Two triangles per quad, counter-clockwise seen from the side u x v points to.
TriangleMesh SurfaceMesh(const std::vector<SurfaceQuad>& quads);

// The nearest t > 0 at which origin + t dir meets a quad; infinity when none. `quad`, when
// given, gets the index of the quad met (unchanged when none).
double NearestHit(const std::vector<SurfaceQuad>& quads, const Eigen::Vector3d& origin,
                  const Eigen::Vector3d& dir, size_t* quad = nullptr);

// The true cameras (image i + 1, camera i + 1, registered, named "image<i>") and, as 3D
// points, the surface points seen through a grid of pixels (every `pixel_step` px, from every
// other image), each with its observations in the images that see it unoccluded (at least two).
Reconstruction SparseModelFromRenderedScene(const RenderedScene& scene, double pixel_step = 24);

}  // namespace varsfm
