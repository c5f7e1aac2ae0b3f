#pragma once
// Stage 5 of the pipeline: a dense oriented point cloud (OUT/dense.ply of `densify`) in, a
// surface mesh with vertex colours out (OUT/mesh.ply), by mesh/surface.h.
#include <filesystem>

#include <nlohmann/json.hpp>

#include "varsfm/mesh/mesh_topology.h"
#include "varsfm/mesh/photometric_refinement.h"
#include "varsfm/mesh/surface.h"
#include "varsfm/mesh/surface_input.h"
#include "varsfm/util/option_check.h"

namespace varsfm {

struct MeshOptions {
  std::filesystem::path input;   // PLY point cloud (normals needed for Poisson)
  std::filesystem::path output;  // folder; OUT/mesh.ply is written
  // The sparse model the cloud was made from (a model folder or its parent): the camera centres
  // of the visibility beside the cloud (INPUT.vis), which the Delaunay surface needs when the
  // PLY holds none (surface_input.h). Empty: INPUT's folder/sparse.
  std::filesystem::path sparse;
  // Every N-th registered image (scene/holdout.h) is not one of the views that judge the long
  // faces (0: none): what densify and texture held out, mesh leaves out too.
  int holdout = 0;
  // A cloud of more points than this is read merged to this many (mesh/merged_read.h); 0 stands
  // for the points that half of three quarters of the usable memory holds (InputPointsWithin).
  size_t max_read_points = 0;
  // surface.delaunay.max_merged_points 0 stands for the points whose surface fits in three
  // quarters of the usable memory (MergedPointsWithin, util/usable_memory.h).
  SurfaceOptions surface;
  // Photometric refinement of the surface (mesh/photometric_refinement.h) from the photos in
  // image_dir, sampled with their longer side at most refinement_max_image_size pixels (smaller
  // where they would take more than a quarter of the usable memory together); none without
  // image_dir or with 0 iterations.
  PhotometricRefinementOptions refinement;
  std::filesystem::path image_dir;
  int refinement_max_image_size = 2000;

  // Throws OptionError (util/option_check.h) for a bad value; files are checked when the stage
  // runs.
  void Check() const;
};

struct MeshSummary {
  SurfaceStats stats;
  size_t file_points = 0;  // points in the input file
  double read_voxel = 0;   // where the cloud was read merged, the merge voxel; 0: read whole
  size_t num_vertices = 0;
  size_t num_faces = 0;
  PhotometricRefinementStats refinement;
  EdgeTopology topology;
  double seconds = 0;
};

// The Delaunay surface's peak memory (delaunay_surface.h): about kBytesPerInputPoint a point of
// the cloud read and kBytesPerMergedPoint a merged point. `varsfm mesh` on the 2.2 M dense points
// of 200 rendered street photos, merged to 243 k, 476 k and 1.05 M points: 903, 1258 and 2093 MB.
inline constexpr size_t kBytesPerInputPoint = 256;
inline constexpr size_t kBytesPerMergedPoint = 1536;
// A cap never goes below this: a surface worth texturing needs some points, and a machine
// without 150 MB to spare for them would fail anyway.
inline constexpr size_t kMinMergedPoints = 100000;

// The merged points whose surface, made from a cloud of `input_points`, fits in `bytes`; at
// least kMinMergedPoints.
size_t MergedPointsWithin(size_t bytes, size_t input_points);

// The points of a cloud read whole that take at most half of `bytes`, leaving the other half to
// its surface; at least kMinMergedPoints. A larger cloud is read merged to this many.
size_t InputPointsWithin(size_t bytes);

// Throws varsfm::Error (one line naming the file) for a missing, unreadable or empty PLY, one
// without normals when the method is Poisson, one without visibility (in the PLY, or INPUT.vis
// with the sparse model) when it is Delaunay, or a mesh that fails the check (mesh_quality.h).
MeshSummary RunMesh(const MeshOptions& options, OptionsCheck check = OptionsCheck::kByStage);

// The figures summary.json keeps of a mesh stage: points (in the file), the points the surface
// was made of (merged or downsampled), octree depth, vertices, faces, median vertex-to-point
// distance, the cloud's extent, their ratio, seconds, the Delaunay surface's merge spacing, the
// voxel of a cloud read merged, and the photometric refinement's figures.
nlohmann::json MeshSummaryJson(const MeshSummary& result);

}  // namespace varsfm
