#pragma once
// Advancing-front surface reconstruction (Cohen-Steiner & Da 2004, through CGAL): like the 3D
// Crust the paper uses, it picks faces of the points' Delaunay triangulation, so the vertices
// are data points. Selectable beside the default screened Poisson.
#include "varsfm/scene/point_cloud.h"
#include "varsfm/scene/triangle_mesh.h"

namespace varsfm {

// Oriented like the input normals when the cloud has them. Throws varsfm::Error without faces.
TriangleMesh ReconstructAdvancingFront(const PointCloud& cloud);

}  // namespace varsfm
