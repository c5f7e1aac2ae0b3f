#pragma once
// Decimation to a face budget: edge collapses in order of the Garland-Heckbert quadric error
// ("Surface simplification using quadric error metrics", SIGGRAPH 1997; CGAL's
// Surface_mesh_simplification), each collapsed vertex placed where the summed squared
// distances to its faces' planes are least, so flat areas (walls, the ground) lose faces first
// and edges and corners keep theirs. A model for the web or a phone wants a few hundred
// thousand faces, not the millions a dense cloud gives.
#include <cstddef>

#include "varsfm/scene/triangle_mesh.h"

namespace varsfm {

struct DecimationOptions {
  size_t max_faces = 0;  // 0: keep every face

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

// Collapses edges until at most options.max_faces faces remain (a mesh already within the
// budget is left as it is). Vertex colours are dropped (the caller colours the new vertices);
// non-manifold vertices are split first, as CGAL's halfedge structure needs. Deterministic.
// Returns the number of faces removed.
size_t DecimateMesh(const DecimationOptions& options, TriangleMesh* mesh);

}  // namespace varsfm
