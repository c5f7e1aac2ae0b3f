#pragma once
// How close a dense cloud lies to the sparse model it grew from (issue 6's acceptance check):
// for each dense point, the distance to the nearest sparse 3D point, and the distance to the
// plane through its k nearest sparse points (which, unlike the first, does not grow with the
// spacing of the sparse points on a surface the dense points sample finely). Both are reported
// in scene units: divided by the median depth of the sparse points in the cameras that see
// them (the typical camera-to-scene distance), so figures compare across datasets.
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "varsfm/scene/reconstruction.h"

namespace varsfm {

struct SparseDistanceStats {
  size_t num_checked = 0;          // dense points measured (a deterministic subsample)
  double scene_depth = 0;          // median camera-to-point depth of the sparse model
  double median_nearest = 0;       // median distance to the nearest sparse point / scene_depth
  double median_plane = 0;         // median distance to the local sparse plane / scene_depth
  double fraction_within_1pc = 0;  // share of checked points with plane distance < 1 % depth
};

// Distances for at most `max_checked` dense points (every n-th, so the result is
// deterministic); k sparse neighbours define the plane. Throws varsfm::Error when the model
// has fewer than k sparse points or the cloud is empty.
SparseDistanceStats MeasureAgainstSparse(const std::vector<Eigen::Vector3d>& dense,
                                         const Reconstruction& reconstruction, int k = 8,
                                         size_t max_checked = 20000);

}  // namespace varsfm
