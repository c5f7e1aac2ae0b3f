#pragma once
// Triangulation of a newly registered image's 2D points (step 2 of Algorithm 1 of El Hazzat et
// al.): a point continues an existing track where one of its matches has a 3D point that
// reprojects well in the new image; otherwise a new 3D point is triangulated from every
// registered view that sees it.
#include <cstddef>

#include "varsfm/scene/reconstruction.h"
#include "varsfm/sfm/correspondence_graph.h"

namespace varsfm {

struct TrackTriangulationOptions {
  // Largest reprojection error (px) of an observation that joins a track or a new point.
  double max_error_px = 4.0;
  // A new point needs two of its views this far apart as seen from it: below it the depth is
  // poorly determined (COLMAP's default).
  double min_angle_deg = 1.5;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

// Triangulates the 2D points of registered image `image_id` that have no 3D point yet: each
// joins an existing track or makes a new 3D point. Returns the number of new 3D points.
size_t TriangulateImage(const CorrespondenceGraph& graph, const TrackTriangulationOptions& options,
                        image_t image_id, Reconstruction* rec);

}  // namespace varsfm
