#pragma once
// Surface reconstruction from a dense point cloud: Poisson (Kazhdan, Bolitho, Hoppe 2006, as
// CGAL implements it: implicit function solved on a refined Delaunay triangulation, contoured by
// Delaunay surface meshing) or advancing-front (Cohen-Steiner & Da 2004; like the 3D Crust the
// paper uses, it picks faces of the points' Delaunay triangulation, so vertices are data points).
#include <filesystem>
#include <string>

#include "varsfm/io/ply.h"
#include "varsfm/mesh/triangle_mesh.h"

namespace varsfm {

enum class SurfaceMethod { kPoisson, kAdvancingFront };

struct SurfaceOptions {
  SurfaceMethod method = SurfaceMethod::kPoisson;
  // Voxel-grid downsampling before reconstruction when the cloud has more points than this
  // (the voxel grows until it fits): CGAL's Poisson cost grows quickly with the point count.
  size_t max_points = 60000;
  // Poisson only: faces with a vertex farther than trim_factor x the average point spacing from
  // every input point are removed, so the closed implicit surface does not balloon over holes.
  // <= 0 keeps the whole surface.
  double trim_factor = 3.0;
  // Poisson only: CGAL's surface-mesher approximation distance in units of the average spacing
  // (smaller: finer, slower). CGAL's default is 0.375.
  double approximation_distance = 0.375;
};

struct SurfaceStats {
  size_t input_points = 0;
  size_t used_points = 0;  // after downsampling
  double average_spacing = 0;
  size_t faces_before_trim = 0;
};

// Throws varsfm::Error when the cloud has too few points, lacks normals (Poisson), or the
// reconstruction fails. Vertex colours come from the nearest input point when it has colours.
TriangleMesh ReconstructSurface(const PointCloud& cloud, const SurfaceOptions& options,
                                SurfaceStats* stats = nullptr);

// Reads the PLY a surface is built from. Throws varsfm::Error (one line naming the file) when it
// is missing, unreadable, empty, or lacks normals that `method` needs.
PointCloud ReadSurfaceInput(const std::filesystem::path& file, SurfaceMethod method);

// "poisson" / "afront"; throws varsfm::Error for anything else.
SurfaceMethod ParseSurfaceMethod(const std::string& name);

}  // namespace varsfm
