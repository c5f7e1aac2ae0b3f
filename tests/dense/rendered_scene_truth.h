#pragma once
// Exact truth of RenderSyntheticScene's geometry for dense tests, beyond what
// synthetic/rendered_truth.h gives (ray casts, the sparse model of true cameras).
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "varsfm/synthetic/rendered_scene.h"
#include "varsfm/synthetic/rendered_truth.h"

namespace varsfm::testing {

// Distance from a point to the nearest face plane, and that plane's unit normal.
inline double PlaneDistance(const std::vector<SurfaceQuad>& quads, const Eigen::Vector3d& x,
                            Eigen::Vector3d* normal) {
  double best = std::numeric_limits<double>::infinity();
  for (const SurfaceQuad& q : quads) {
    const Eigen::Vector3d n = q.u.cross(q.v).normalized();
    const double d = std::abs(n.dot(x - q.origin));
    if (d < best) best = d, *normal = n;
  }
  return best;
}

}  // namespace varsfm::testing
