#pragma once
// Photo-consistency check of the views that see a face (Waechter, Moehrle & Goesele, "Let there
// be color!", ECCV 2014, sec. 3.1): a view whose mean colour of the face disagrees with the
// consensus of the others shows something that is not the surface -- an occluder missing from
// the mesh (a branch in front of a roof, a person walking by) -- and is removed from the face's
// candidates.
//
// Waechter et al. shift a Gaussian with the inliers' covariance; with the 3-6 views of a face
// that small photo sets give, a covariance fitted to the views themselves cannot single out an
// outlier (no point of 3 lies more than 1.16 of their own standard deviations from their mean).
// So the consensus is found by mean shift with a fixed bandwidth in colour space (Comaniciu &
// Meer 2002): the densest mode, started from every view's colour, and views farther than
// `reject_distance` bandwidths from it are rejected -- only when the mode is held by a strict
// majority of the views, so two views that disagree with each other both stay.
#include <array>
#include <vector>

#include <Eigen/Core>

#include "varsfm/texture/face_observations.h"

namespace varsfm {

struct PhotoConsistencyOptions {
  bool enabled = true;
  double bandwidth = 20.0;       // grey levels (BGR Euclidean), after the exposure gains
  double reject_distance = 2.5;  // in bandwidths
  void Check() const;
};

// Sets every view's distance from the consensus where a strict majority holds it
// (FaceObservations::deviation, for view selection's consensus term), and the quality of rejected
// (view, face) observations to 0, and of the same view at the rejected faces' edge neighbours that
// another view sees; returns their number. Colours are compared after multiplying by each view's
// gain. `neighbours`: face_adjacency.h.
size_t RejectInconsistentViews(const std::vector<Eigen::Vector3f>& gains,
                               const std::vector<std::array<int, 3>>& neighbours,
                               const PhotoConsistencyOptions& options,
                               FaceObservations* observations);

}  // namespace varsfm
