#pragma once
// The long faces of the visibility cut's surface (delaunay_surface.h). Where the cut closes the
// inside volume across space no point sampled -- along the convex hull, behind a facade, from a
// roofline to the trees, over the sky -- it does so with facets between far-apart points, which
// lie off any true surface; they are removed. But a weakly textured surface the cameras do see (a
// felt puppet's torso, a plaster wall between textured parts) has few points too, and the cut
// spans it with long facets that are right: removing them opens a hole in the object.
//
// What tells the two apart is how the views see them. Rendered into a view, a long facet over a
// weak surface fills a hole that the rest of the surface encloses: every pixel around it shows a
// face that is kept, at the hole's depth or in front of it. A facet across space reaches the open
// background, the image's edge, or lies in front of a farther surface it would hide. A long
// face is kept when some view sees it in an enclosed hole and no view sees it reach the open
// (an option, LongFaceOptions::keep_enclosed).
#include <cstddef>
#include <vector>

#include "varsfm/geometry/posed_camera.h"
#include "varsfm/scene/triangle_mesh.h"

namespace varsfm {

struct LongFaceOptions {
  // Faces with an edge longer than this many times the surface's median edge length are long
  // (0: none is).
  double max_edge_factor = 8.0;
  // Whether long faces that views see enclosed by the kept surface stay (the views given). Off
  // by default: it closes holes in objects (kermit's torso, entry-P10's doorway), but the faces
  // it keeps are weakly seen and their texture is poor -- 13-20 dB on the held-out pixels they
  // add, so the held-out PSNR falls on every shared set for 0.1-1.3 points of coverage
  // (bench/results/2026-12-05-s19-enclosed-long-faces.md).
  bool keep_enclosed = false;
  // The views are rasterised at this size (longer side, px): the holes that matter span tens of
  // pixels at it, and a few hundred thousand faces rasterise in milliseconds.
  int raster_size = 400;
  // A pixel around a hole encloses it when its kept face is at most this factor farther than
  // the hole's pixel beside it (nearer: an occluder in front, which also encloses); ...
  double max_depth_ratio = 1.1;
  // ... and a hole is enclosed when this fraction of the pixels around it do.
  double min_enclosed_fraction = 0.9;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

struct LongFaceStats {
  size_t long_faces = 0;  // faces with an edge above max_edge_factor x the median
  size_t kept = 0;        // of them, kept as enclosed holes' fillings
};

// Removes the long faces but those `views` see in enclosed holes. Deterministic for any thread
// count (parallel over views).
LongFaceStats RemoveLongFaces(const LongFaceOptions& options, const std::vector<PosedCamera>& views,
                              TriangleMesh* mesh);

}  // namespace varsfm
