#include "varsfm/mesh/surface_input.h"

#include <map>

#include "varsfm/io/colmap_model.h"
#include "varsfm/io/ply.h"
#include "varsfm/mesh/merged_read.h"
#include "varsfm/scene/holdout.h"
#include "varsfm/util/error.h"

namespace varsfm {
void AttachVisibility(const PointVisibility& visibility, const Reconstruction& model,
                      PointCloud* cloud) {
  if (visibility.size() != cloud->points.size())
    Fail("visibility of {} points for a cloud of {}", visibility.size(), cloud->points.size());
  std::map<image_t, uint32_t> index;  // ascending ids -> ascending viewpoint indices
  for (const std::vector<image_t>& ids : visibility)
    for (image_t id : ids) index.emplace(id, 0);
  std::vector<Eigen::Vector3d> viewpoints;
  viewpoints.reserve(index.size());
  for (auto& [id, i] : index) {
    if (!model.ExistsImage(id) || !model.image(id).registered)
      Fail("image {} sees a point but is not a registered image of the model", id);
    i = static_cast<uint32_t>(viewpoints.size());
    viewpoints.push_back(model.image(id).Center());
  }
  cloud->viewpoints = std::move(viewpoints);
  cloud->visibility.assign(visibility.size(), {});
  for (size_t p = 0; p < visibility.size(); ++p) {
    std::vector<uint32_t>& views = cloud->visibility[p];
    views.reserve(visibility[p].size());
    for (image_t id : visibility[p]) views.push_back(index.at(id));
  }
}

std::filesystem::path SparseModelFolder(const std::filesystem::path& file,
                                        const std::filesystem::path& sparse) {
  return sparse.empty() ? file.parent_path() / "sparse" : sparse;
}

SurfaceInput ReadSurfaceInput(const std::filesystem::path& file, SurfaceMethod method,
                              const std::filesystem::path& sparse, int holdout, size_t max_points) {
  if (!std::filesystem::is_regular_file(file)) Fail("{}: no such point cloud", file.string());
  SurfaceInput input;
  bool own_visibility = false;
  {
    const PlyPointReader header(file);
    input.file_points = header.size();
    if (input.file_points == 0) Fail("{}: the point cloud is empty", file.string());
    if (method == SurfaceMethod::kScreenedPoisson && !header.has_normals())
      Fail("{}: Poisson reconstruction needs normals (nx ny nz); try --method afront",
           file.string());
    own_visibility = header.has_visibility();
  }
  std::filesystem::path vis = file;
  vis += ".vis";
  const bool delaunay = method == SurfaceMethod::kDelaunay;
  if (delaunay && !own_visibility && !std::filesystem::is_regular_file(vis))
    Fail(
        "{}: the Delaunay surface needs the points' visibility, in the PLY or beside it as {} "
        "(written by densify); try --method poisson",
        file.string(), vis.filename().string());
  const std::filesystem::path model_dir = SparseModelFolder(file, sparse);
  const bool vis_beside = delaunay && !own_visibility;
  PointCloud& cloud = input.cloud;
  PointVisibility merged_ids;
  if (max_points > 0 && input.file_points > max_points) {
    MergedRead read = ReadMerged(file, vis_beside ? vis : std::filesystem::path(), max_points);
    cloud = std::move(read.cloud);
    merged_ids = std::move(read.image_ids);
    input.read_voxel = read.voxel;
  } else {
    cloud = ReadPly(file);
  }
  if (!delaunay) return input;
  // A cloud with its own visibility (match propagation's) needs no model: without one beside it,
  // every long face goes.
  if (own_visibility && !std::filesystem::exists(model_dir)) return input;
  Reconstruction model = ReadColmapModel(model_dir);
  if (vis_beside) {
    try {
      if (input.WasReadMerged())
        AttachVisibility(merged_ids, model, &cloud);
      else
        AttachVisibility(ReadPointVisibility(vis), model, &cloud);
    } catch (const Error& e) {
      Fail("{} with the model in {}: {}", vis.string(), model_dir.string(), e.what());
    }
  }
  HoldOutImages(&model, holdout);  // once the visibility (any registered image) is attached
  for (const auto& [id, image] : model.images())
    if (image.registered) input.views.push_back({model.CameraOf(id), image.cam_from_world});
  return input;
}

}  // namespace varsfm
