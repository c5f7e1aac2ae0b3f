#pragma once
// How well a two-view reconstruction determines its focal lengths: the standard deviation of
// log f1 and log f2 from the Gauss-Newton information matrix of the reprojection errors
// (J^T J / sigma^2), with the 3D points eliminated by the Schur complement and the pose of the
// second camera (rotation, and translation direction: the scale is the gauge) marginalised.
// Near-degenerate pairs (optical axes nearly meeting, little parallax, a nearly planar
// scene) leave f free along a valley of equal cost: the standard deviation then grows by
// orders of magnitude, which is the "large uncertainty of log f" test of the issue and of
// docs/self_calibration.md.
#include <optional>
#include <utility>

#include "varsfm/scene/reconstruction.h"

namespace varsfm {

// `rec` holds images 1 and 2 (image 1 the gauge, its pose held) with cameras whose focal
// lengths are the unknowns, and points observed by both. `sigma_px`: pixel noise per
// coordinate; `with_distortion`: k1, k2 of each camera are unknowns too (else held).
// Returns nullopt when the information matrix is singular (f undetermined).
std::optional<std::pair<double, double>> TwoViewLogFocalStdDev(const Reconstruction& rec,
                                                               image_t image_id1, image_t image_id2,
                                                               double sigma_px,
                                                               bool with_distortion);

}  // namespace varsfm
