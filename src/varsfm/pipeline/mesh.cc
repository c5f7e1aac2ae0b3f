#include "varsfm/pipeline/mesh.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <system_error>

#include <opencv2/imgproc.hpp>

#include "varsfm/io/mesh_ply.h"
#include "varsfm/io/model_photo.h"
#include "varsfm/io/ply.h"
#include "varsfm/pipeline/output_folder.h"
#include "varsfm/pipeline/stage_model.h"
#include "varsfm/scene/holdout.h"
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"
#include "varsfm/util/path_lock.h"
#include "varsfm/util/timer.h"
#include "varsfm/util/usable_memory.h"

namespace varsfm {

void MeshOptions::Check() const {
  CheckHoldout(holdout);
  if (max_read_points != 0) CheckAtLeast("--max-read-points", max_read_points, size_t{10});
  surface.Check();
  refinement.Check();
  CheckAtLeast("--refinement-max-image-size", refinement_max_image_size, 100);
}

namespace {

// The registered photos the refinement samples: gray, in [0, 1], longer side at most
// `max_image_size`, each with its camera at that size; all of them smaller by the same factor
// where they would take more than `max_bytes` together (a large capture on a small machine).
std::vector<RefinementView> ReadRefinementViews(const Reconstruction& rec,
                                                const std::filesystem::path& image_dir,
                                                int max_image_size, size_t max_bytes) {
  const auto size_scale = [&](const Camera& camera) {
    return std::min(1.0,
                    static_cast<double>(max_image_size) / std::max(camera.width, camera.height));
  };
  double bytes = 0;
  for (const auto& [id, image] : rec.images())
    if (image.registered) {
      const Camera& camera = rec.CameraOf(id);
      const double scale = size_scale(camera);
      bytes += sizeof(float) * scale * scale * camera.width * camera.height;
    }
  const double memory_scale = bytes > static_cast<double>(max_bytes)
                                  ? std::sqrt(static_cast<double>(max_bytes) / bytes)
                                  : 1.0;
  if (memory_scale < 1)
    info(
        "mesh: the photometric refinement samples the photos at {:.0f} % of {} px, to hold them "
        "in {} MB",
        100 * memory_scale, max_image_size, max_bytes >> 20);
  std::vector<RefinementView> views;
  for (const auto& [id, image] : rec.images()) {
    if (!image.registered) continue;
    const cv::Mat photo = ReadModelPhoto(rec, id, image_dir);
    cv::Mat gray;
    cv::cvtColor(photo, gray, cv::COLOR_BGR2GRAY);
    const double scale = size_scale(rec.CameraOf(id)) * memory_scale;
    const int width = std::max(1, static_cast<int>(std::lround(gray.cols * scale)));
    const int height = std::max(1, static_cast<int>(std::lround(gray.rows * scale)));
    if (width != gray.cols || height != gray.rows)
      cv::resize(gray, gray, cv::Size(width, height), 0, 0, cv::INTER_AREA);
    views.push_back(
        RefinementViewOf(gray, {rec.CameraOf(id).Resized(width, height), image.cam_from_world}));
  }
  return views;
}

}  // namespace

size_t MergedPointsWithin(size_t bytes, size_t input_points) {
  const size_t input_bytes = input_points * kBytesPerInputPoint;
  const size_t left = bytes > input_bytes ? bytes - input_bytes : 0;
  return std::max(left / kBytesPerMergedPoint, kMinMergedPoints);
}

size_t InputPointsWithin(size_t bytes) {
  return std::max(bytes / 2 / kBytesPerInputPoint, kMinMergedPoints);
}

MeshSummary RunMesh(const MeshOptions& options, OptionsCheck check) {
  if (check == OptionsCheck::kByStage) options.Check();
  OutputFolderLock output_lock(options.output);
  Timer timer;
  const size_t memory = UsableMemoryBytes() / 4 * 3;
  const SurfaceInput input = ReadSurfaceInput(
      options.input, options.surface.method, options.sparse, options.holdout,
      options.max_read_points > 0 ? options.max_read_points : InputPointsWithin(memory));
  // The refinement's model and photos are looked for before the surface is built: a wrong
  // --images fails at once, not after it.
  const bool refine = options.refinement.iterations > 0 && !options.image_dir.empty();
  std::optional<Reconstruction> refinement_model;
  if (refine)
    refinement_model = ReadStageModel("mesh", SparseModelFolder(options.input, options.sparse),
                                      options.image_dir, options.holdout, 2);
  SurfaceOptions surface = options.surface;
  if (surface.delaunay.max_merged_points == 0)
    surface.delaunay.max_merged_points = MergedPointsWithin(memory, input.cloud.points.size());
  MeshSummary result;
  result.file_points = input.file_points;
  result.read_voxel = input.read_voxel;
  TriangleMesh mesh;
  try {
    mesh = ReconstructSurface(input.cloud, surface, &result.stats, input.views);
  } catch (const Error& e) {
    Fail("{}: {}", options.input.string(), e.what());
  }
  if (options.refinement.iterations > 0 && options.image_dir.empty())
    info("mesh: no photometric refinement (it needs the photos: --images)");
  if (refine) {
    Timer refinement_timer;
    result.refinement = RefinePhotometrically(
        ReadRefinementViews(*refinement_model, options.image_dir, options.refinement_max_image_size,
                            UsableMemoryBytes() / 4),
        options.refinement, &mesh);
    info(
        "mesh: photometric refinement, {} iterations: {} vertices measured at the last, mean "
        "offset {:.3g}, in {:.1f} s",
        options.refinement.iterations, result.refinement.measured_vertices,
        result.refinement.mean_offset, refinement_timer.Seconds());
  }
  output_lock.CreateAndLock();
  RemoveOutputsAfter(options.output, ChainStage::kMesh);
  WriteMeshPly(options.output / "mesh.ply", mesh);

  result.num_vertices = mesh.vertices.size();
  result.num_faces = mesh.faces.size();
  result.topology = ComputeEdgeTopology(mesh);
  result.seconds = timer.Seconds();
  const MeshQuality& q = result.stats.quality;
  spdlog::info(
      "mesh: {} vertices, {} faces ({} boundary, {} non-manifold edges), median distance to the "
      "points {:.4g} = {:.3f} % of the extent {:.4g}, in {:.1f} s -> {}",
      result.num_vertices, result.num_faces, result.topology.boundary_edges,
      result.topology.non_manifold_edges, q.median_distance, 100 * q.RelativeDistance(), q.extent,
      result.seconds, (options.output / "mesh.ply").string());
  return result;
}

nlohmann::json MeshSummaryJson(const MeshSummary& result) {
  const MeshQuality& q = result.stats.quality;
  nlohmann::json json = {
      {"points", result.file_points}, {"surface_points", result.stats.used_points},
      {"depth", result.stats.depth},  {"vertices", result.num_vertices},
      {"faces", result.num_faces},    {"median_distance", q.median_distance},
      {"extent", q.extent},           {"relative_distance", q.RelativeDistance()},
      {"seconds", result.seconds}};
  // The Delaunay surface's merge voxel in point spacings: above --merge-spacing where the memory
  // cap merged more coarsely.
  if (result.stats.delaunay.merge_voxel > 0 && result.stats.average_spacing > 0)
    json["merge_spacing"] = result.stats.delaunay.merge_voxel / result.stats.average_spacing;
  // A cloud larger than the memory: read merged at this voxel (scene units) before all else.
  if (result.read_voxel > 0) json["read_merge_voxel"] = result.read_voxel;
  // The photometric refinement, where it ran: vertices measured at its last iteration, and the
  // mean distance a vertex moved per iteration (scene units).
  if (result.refinement.measured_vertices > 0)
    json["refinement"] = {{"measured_vertices", result.refinement.measured_vertices},
                          {"mean_offset", result.refinement.mean_offset}};
  return json;
}

}  // namespace varsfm
