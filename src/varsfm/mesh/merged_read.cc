#include "varsfm/mesh/merged_read.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "varsfm/io/ply.h"
#include "varsfm/mesh/nearest_points.h"
#include "varsfm/mesh/point_grid.h"
#include "varsfm/util/error.h"
#include "varsfm/util/even_sample.h"
#include "varsfm/util/log.h"

namespace varsfm {
namespace {

// Points of the first pass's even sample: enough for a spacing within a few per cent, few enough
// for its k-d tree to cost nothing beside the merge.
constexpr size_t kSpacingSample = 100000;

// How much wider than the mean nearest-neighbour spacing the side of the area a point stands for
// is: 1 on a regular grid, 2 for points at random on a surface (their mean nearest-neighbour
// distance is 1 / (2 sqrt(density)), Clark & Evans 1954). Dense clouds lie between: merging
// fountain-P11's and kermit's to 100 k and 400 k points took 1.6 to 2.2. Below what a cloud
// needs, a pass overshoots and the voxel grows; above it, fewer points remain than allowed.
constexpr double kAreaSideOverSpacing = 1.5;

// The voxel expected to leave about max_points of the file's points: the sample's spacing scaled
// to the whole cloud (x sqrt(sample / n)), then to the area max_points voxels share.
double FirstVoxel(const std::filesystem::path& file, size_t max_points, MergedRead* read) {
  PlyPointReader reader(file);
  EvenSample<Eigen::Vector3d> sample(kSpacingSample);
  PlyPoint point;
  for (size_t i = 0; i < reader.size(); ++i) {
    reader.Next(&point);
    sample.Add(point.position);
  }
  read->file_points = reader.size();
  ++read->passes;
  const double sample_spacing = AverageNearestSpacing(sample.items());
  const double n = static_cast<double>(reader.size());
  const double spacing = sample_spacing * std::sqrt(sample.items().size() / n);
  const double voxel =
      kAreaSideOverSpacing * spacing * std::sqrt(n / static_cast<double>(max_points));
  if (!(voxel > 0) || !std::isfinite(voxel))
    Fail("{}: its points have no spread to merge over", file.string());
  return voxel;
}

}  // namespace

MergedRead ReadMerged(const std::filesystem::path& file,
                      const std::filesystem::path& visibility_file, size_t max_points) {
  if (max_points < kMinMergedReadPoints)
    Fail("ReadMerged: at most {} points asked for; at least {} remain", max_points,
         kMinMergedReadPoints);
  const bool with_ids = !visibility_file.empty();
  if (with_ids) {  // before the first pass over a large file
    const PointVisibilityReader ids(visibility_file);
    const PlyPointReader points(file);
    if (ids.size() != points.size())
      Fail("{}: visibility of {} points for a cloud of {}", visibility_file.string(), ids.size(),
           points.size());
  }
  MergedRead read;
  const double first_voxel = FirstVoxel(file, max_points, &read);
  double voxel = first_voxel;
  PlyPoint point;
  std::vector<image_t> ids;
  for (;;) {
    ++read.passes;
    PlyPointReader reader(file);
    std::optional<PointVisibilityReader> ids_reader;
    if (with_ids) ids_reader.emplace(visibility_file);
    // The ids beside the file, where given, stand for its own visibility.
    VoxelMerge merge(voxel, reader.has_normals(), reader.has_colors(),
                     reader.has_visibility() || with_ids);
    size_t i = 0;
    for (; i < reader.size() && merge.size() <= max_points; ++i) {
      reader.Next(&point);
      if (with_ids) ids_reader->Next(&ids);
      merge.Add(point.position, point.normal, point.color, with_ids ? ids : point.visibility);
    }
    if (merge.size() > max_points) {
      const double projected =
          static_cast<double>(merge.size()) * static_cast<double>(reader.size()) / i;
      voxel *= std::max(1.1, 1.02 * std::sqrt(projected / static_cast<double>(max_points)));
      continue;
    }
    if (with_ids) ids_reader->ExpectEnd();
    read.cloud = std::move(merge).Result();
    read.cloud.viewpoints = reader.ReadViewpoints();
    if (with_ids) {
      read.image_ids = std::move(read.cloud.visibility);
      read.cloud.visibility.clear();
      read.cloud.viewpoints.clear();
    }
    break;
  }
  read.voxel = voxel;
  spdlog::info(
      "{}: {} points read merged at voxel {:.4g} to {} (at most {}; first voxel tried {:.4g}, {} "
      "passes over the file)",
      file.string(), read.file_points, voxel, read.cloud.points.size(), max_points, first_voxel,
      read.passes);
  return read;
}

}  // namespace varsfm
