#pragma once
// Triangulation of 3D points from their projections (Hartley & Zisserman, chapter 12): the
// linear DLT method (section 12.2) and a non-linear refinement of the pixel reprojection error
// through the full camera model, distortion included.
#include <vector>

#include <Eigen/Core>

#include "varsfm/camera/camera.h"
#include "varsfm/geometry/rigid3.h"
#include "varsfm/util/types.h"

namespace varsfm {

// Linear two-view triangulation: x ~ P X for both views. x1, x2 are in the coordinates of the
// projection matrices (pixels with K [R|t], normalised with [R|t]). Returns false when the
// solution is at infinity.
bool TriangulatePoint(const Matrix34d& P1, const Matrix34d& P2, const Eigen::Vector2d& x1,
                      const Eigen::Vector2d& x2, Eigen::Vector3d* point);

// Linear multi-view triangulation from >= 2 views (H&Z section 12.2, one pair of rows of
// A X = 0 per view; each pair scaled to unit norm so no view dominates).
bool TriangulateMultiView(const std::vector<Matrix34d>& Ps, const std::vector<Eigen::Vector2d>& xs,
                          Eigen::Vector3d* point);

// Refines `point` to minimise the sum of squared pixel reprojection errors over the views
// (Levenberg-Marquardt with the analytic Jacobian of varsfm::Camera projection). Returns false
// (leaving `point` unchanged) when the point is behind a camera or the problem is singular.
bool RefineTriangulatedPoint(const std::vector<Camera>& cameras,
                             const std::vector<Rigid3d>& cams_from_world,
                             const std::vector<Eigen::Vector2d>& pixels, Eigen::Vector3d* point,
                             int max_iterations = 20);

// Pixel reprojection error of a world point in one view (infinity when behind the camera).
double ReprojectionError(const Camera& camera, const Rigid3d& cam_from_world,
                         const Eigen::Vector2d& pixel, const Eigen::Vector3d& point);

// The angle (radians) between the viewing rays from two camera centres to `point`.
double TriangulationAngle(const Eigen::Vector3d& center1, const Eigen::Vector3d& center2,
                          const Eigen::Vector3d& point);

// Cheirality: the point lies in front of the camera (positive depth).
bool HasPositiveDepth(const Rigid3d& cam_from_world, const Eigen::Vector3d& point);

// Depth of a point for an arbitrary-scale projection matrix (H&Z eq. 6.15):
// depth = sign(det M) w / ||m3||, with (., ., w) = P (X, 1). Positive in front of the camera.
double ProjectionDepth(const Matrix34d& P, const Eigen::Vector3d& point);

}  // namespace varsfm
