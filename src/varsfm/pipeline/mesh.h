#pragma once
// Stage 5 of the pipeline: a dense oriented point cloud (OUT/dense.ply of `densify`) in, a
// surface mesh with vertex colours out (OUT/mesh.ply), by mesh/surface.h.
#include <filesystem>

#include "varsfm/mesh/surface.h"
#include "varsfm/mesh/triangle_mesh.h"

namespace varsfm {

struct MeshCommandOptions {
  std::filesystem::path input;   // PLY point cloud (normals needed for Poisson)
  std::filesystem::path output;  // folder; OUT/mesh.ply is written
  SurfaceOptions surface;
};

struct MeshCommandResult {
  SurfaceStats stats;
  size_t num_vertices = 0;
  size_t num_faces = 0;
  EdgeTopology topology;
  double seconds = 0;
};

// Throws varsfm::Error (one line naming the file) for a missing, unreadable or empty PLY, or
// one without normals when the method is Poisson.
MeshCommandResult RunMesh(const MeshCommandOptions& options);

}  // namespace varsfm
