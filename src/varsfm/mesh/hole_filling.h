#pragma once
// Closing the small holes of a surface: boundary loops short against the surface's edge length
// are triangulated over their own vertices (Liepa, "Filling holes in meshes", SGP 2003, through
// CGAL's triangulate_hole_polyline: the triangulation of the loop that minimises the largest
// dihedral angle, with the faces beside the loop, then the area), then optionally refined and
// faired (hole_fairing.h, the rest of Liepa's method). The visibility cut leaves such
// holes where the dense points are missing or too noisy on a surface the cameras do see (fur,
// weak texture, specular spots); long loops, the scene's open edge against the sky or the
// ground's end, stay open.
#include <cstddef>

#include "varsfm/scene/triangle_mesh.h"

namespace varsfm {

struct HoleFillingOptions {
  // A loop is filled when it has at most max_edges edges and its perimeter is at most
  // max_edges x the surface's median edge length (so a loop of long edges, which spans more
  // than its count suggests, stays open). 0 fills nothing.
  int max_edges = 0;
  // Whether each patch is refined to the density of the surface around it and faired
  // (hole_fairing.h) rather than left as triangles over the loop's own vertices. Off by default:
  // with the default loops it renders held-out views the same (within 0.05 dB on every shared
  // set) and on the rendered synthetic scene, whose surfaces are planes, the faired patches lie a
  // little off them (accuracy 0.994 -> 0.990); with loops of up to 350 edges it cuts the flat
  // patches' held-out loss on four sets and deepens it on fountain-P11-zoom
  // (bench/results/2026-12-07-s37-hole-fairing.md).
  bool refine_and_fair = false;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

struct HoleFillingStats {
  size_t loops = 0;         // boundary loops (through manifold boundary vertices)
  size_t filled_loops = 0;  // of them, closed
  size_t added_faces = 0;
  size_t faired_loops = 0;  // of the filled loops, refined and faired
  size_t added_vertices = 0;
};

// Fills the loops options allow, never the longest loop of a connected part (its outer edge:
// filling it would lay a second sheet over an open surface). Where loops meet at a vertex they
// are split there; an edge of three faces, two of them along it the same way (a flap on a rim),
// carries the boundary of the hole beside it. Faces are added counter-clockwise like the faces
// beside the loop; vertices are added only by refine_and_fair (after the mesh's, with colour
// grey where the mesh has colours). Deterministic. `options` must have passed
// Check() (DelaunaySurfaceOptions::Check checks them where the mesh stage starts).
HoleFillingStats FillSmallHoles(const HoleFillingOptions& options, TriangleMesh* mesh);

}  // namespace varsfm
