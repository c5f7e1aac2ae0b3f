#pragma once
// The point cloud a surface is built from (OUT/dense.ply), with what its method needs: normals
// for screened Poisson; for the Delaunay surface (delaunay_surface.h) the cameras that saw each
// point. Match propagation records those in the PLY itself (a viewpoint element and a list per
// point); PatchMatch's depth-map fusion writes them beside it as OUT/dense.ply.vis, image ids in
// the layout of COLMAP's fused.ply.vis (io/point_visibility.h), whose camera centres come from
// the sparse model the cloud was made from.
#include <filesystem>
#include <vector>

#include "varsfm/io/point_visibility.h"
#include "varsfm/mesh/surface.h"
#include "varsfm/scene/point_cloud.h"
#include "varsfm/scene/reconstruction.h"

namespace varsfm {

// Sets cloud->viewpoints to the centres of the images `visibility` names (ascending ids) and
// cloud->visibility to indices into them (ascending, as the ids). Throws varsfm::Error when the
// counts of points differ or an id is not a registered image of `model`.
void AttachVisibility(const PointVisibility& visibility, const Reconstruction& model,
                      PointCloud* cloud);

struct SurfaceInput {
  PointCloud cloud;
  size_t file_points = 0;  // points in the file; more than the cloud's where it was read merged
  double read_voxel = 0;   // the merge voxel of a cloud read merged (merged_read.h); 0: whole

  bool WasReadMerged() const { return read_voxel > 0; }
  // Delaunay: the registered cameras of the model, which judge the long faces (long_faces.h);
  // empty for the other methods, and for a cloud with its own visibility and no model beside it.
  std::vector<PosedCamera> views;
};

// The sparse model beside a cloud: `sparse`, or where `varsfm run` writes it (`file`'s
// folder/sparse) when `sparse` is empty.
std::filesystem::path SparseModelFolder(const std::filesystem::path& file,
                                        const std::filesystem::path& sparse);

// Reads `file`. Throws varsfm::Error (one line naming the file) when it is missing, unreadable or
// empty, or lacks the normals (Poisson) or visibility (Delaunay) that `method` needs. For the
// Delaunay surface, the model in `sparse` (a model folder or its parent, io/colmap_model.h; an
// empty `sparse` means `file`'s folder/sparse, where `varsfm run` writes it) gives the views,
// and a PLY without its own visibility takes `file`.vis with that model's camera centres. The
// views leave out the model's held-out images (every `holdout`-th, scene/holdout.h; 0: none),
// as densification and texturing do. A file of more than `max_points` points (0: no limit) is
// read merged to at most that many (ReadMerged, merged_read.h).
SurfaceInput ReadSurfaceInput(const std::filesystem::path& file, SurfaceMethod method,
                              const std::filesystem::path& sparse = {}, int holdout = 0,
                              size_t max_points = 0);

}  // namespace varsfm
