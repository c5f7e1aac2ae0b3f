#pragma once
// Screened Poisson surface reconstruction (Kazhdan & Hoppe, "Screened Poisson Surface
// Reconstruction", ACM ToG 2013) through Open3D, which wraps Kazhdan's implementation: the
// indicator function is fitted to the oriented points on an adaptive octree, with a screening
// term (Eq. 4 of the paper) that pulls the zero level set onto the samples, so the surface stays
// on the data instead of the over-smoothed fit of the 2006 method. Open3D is used only here.
#include <vector>

#include "varsfm/scene/point_cloud.h"
#include "varsfm/scene/triangle_mesh.h"

namespace varsfm {

struct ScreenedPoissonSurface {
  TriangleMesh mesh;
  // Per vertex: the sampling density the reconstruction estimated there (the octree depth at
  // which the samples would sit, a log2 scale: one less means half the samples per cell side).
  // Low where the surface bridges regions without data.
  std::vector<double> densities;
};

// `depth`: the octree's maximum depth (a grid of at most 2^depth cells per side over the
// points' bounding cube). `num_threads` >= 1. Throws varsfm::Error when the cloud has no
// normals or the reconstruction yields no faces.
ScreenedPoissonSurface ReconstructScreenedPoisson(const PointCloud& cloud, int depth,
                                                  int num_threads);

}  // namespace varsfm
