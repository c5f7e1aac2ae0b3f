#pragma once
// Whether a reconstructed surface is plausibly the surface of its points: it must lie on them
// and must not be tiny against them. A surface method that balloons (a closed implicit surface
// over a hole), collapses (a blob around an outlier-inflated bounding cube) or crashes its
// mesher produces a mesh failing one of the two tests; the mesh stage then stops with one line
// instead of handing a broken surface to texturing.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "varsfm/mesh/nearest_points.h"
#include "varsfm/scene/triangle_mesh.h"

namespace varsfm {

struct MeshQuality {
  size_t num_points = 0;  // of the cloud the mesh was built from
  size_t num_vertices = 0;
  size_t num_faces = 0;
  double median_distance = 0;  // from the mesh's vertices to their nearest point
  double extent = 0;           // RobustExtent of the points
  double spacing = 0;          // the points' average spacing
  double RelativeDistance() const { return extent > 0 ? median_distance / extent : 0; }
};

struct MeshQualityLimits {
  // The median vertex-to-point distance must stay below this fraction of the extent, or below
  // the point spacing when that is larger: a vertex on the sampled surface itself lies up to
  // about half a spacing from the nearest sample, so a sparse cloud cannot be held closer.
  double max_relative_distance = 0.005;
  // A surface resolving the points at k times their spacing has about 2 N / k^2 faces (a
  // triangulation of N vertices has about 2 N faces); requiring k <= 10 gives N / 50 faces.
  double min_faces_per_point = 0.02;
  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

// The diagonal of the box between the 5th and 95th percentiles of the points' coordinates
// (per axis): the scene's size, unmoved by a few far outliers. 0 for an empty set.
double RobustExtent(const std::vector<Eigen::Vector3d>& points);

// `cloud`: the points the mesh was built from; `spacing`: their average spacing
// (AverageNearestSpacing), kept for the check.
MeshQuality MeasureMeshQuality(const TriangleMesh& mesh, const NearestPoints& cloud,
                               double spacing);

// Throws varsfm::Error, one line naming the figures, when `quality` breaks `limits`.
void CheckMeshQuality(const MeshQuality& quality, const MeshQualityLimits& limits = {});

}  // namespace varsfm
