#pragma once
// Foreground fattening: a matching window that straddles an object's outline is matched by its
// textured side, so the pixels beside the outline, out to about the window's radius, take the
// object's depth (Scharstein & Szeliski, "A taxonomy and evaluation of dense two-frame stereo
// correspondence algorithms", IJCV 2002, sec. 5.3). Against a uniform background (the sky past a
// roofline) such a depth is photo-consistent in every view, and geometrically consistent too, so
// neither check removes it, and the surface gains a rim of sky round the outline. So the depths
// within a few pixels of the open background -- the regions without depth that reach the image's
// border, or that are large (sky between two towers) -- are dropped before fusion. Small holes
// inside a surface are left alone: a blank patch of a wall is fattened by the wall itself, at the
// wall's depth, which is right.
#include <cstddef>

#include "varsfm/dense/patchmatch.h"

namespace varsfm {

struct DepthEdgeOptions {
  // Depths within this many pixels (a square neighbourhood) of the open background are dropped;
  // about the NCC window's radius (patchmatch.h), the reach of fattening. 0: none. Held-out
  // figures: bench/results/2026-12-05-s16-depth-edges.md.
  int erosion_px = 4;
  // The open background: the regions without depth that hold a min_gap_px square (so that a
  // thread of missing pixels does not join a hole to it) and reach the image's border or cover at
  // least large_gap_fraction of the map.
  int min_gap_px = 5;
  double large_gap_fraction = 0.01;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

// Drops (depth 0) the depths beside the map's open background (DepthEdgeOptions). Returns how
// many were dropped.
size_t ErodeDepthEdges(const DepthEdgeOptions& options, DepthMap* map);

}  // namespace varsfm
