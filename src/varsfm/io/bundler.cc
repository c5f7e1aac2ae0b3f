#include "varsfm/io/bundler.h"

#include <fmt/format.h>

#include <cmath>
#include <iterator>
#include <limits>
#include <map>
#include <ostream>

#include "varsfm/util/atomic_file.h"
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;

// How far the camera is from Bundler's model (aspect 1, no skew, principal point at the
// centre): the principal point offset in px, or infinity for an aspect or skew Bundler lacks.
double BundlerModelDeviation(const Camera& camera) {
  const auto& p = camera.params;
  if (p[Camera::kAspect] != 1.0 || p[Camera::kSkew] != 0.0)
    return std::numeric_limits<double>::infinity();
  return camera.PrincipalPointOffset().norm();
}

void WriteList(const Reconstruction& rec, std::ostream& out) {
  for (const auto& [id, image] : rec.images()) out << image.name << '\n';
}

// `file` names the bundle in the warning.
void WriteBundle(const Reconstruction& rec, std::ostream& out, const fs::path& file) {
  std::map<image_t, int> index;  // image id -> Bundler camera index (0-based, list.txt order)
  for (const auto& [id, image] : rec.images()) index.emplace(id, static_cast<int>(index.size()));

  out << "# Bundle file v0.3\n" << fmt::format("{} {}\n", index.size(), rec.points3D().size());
  const Eigen::Matrix3d D = Eigen::Vector3d(1, -1, -1).asDiagonal();
  size_t num_approximated = 0;
  double worst_deviation = 0.0;
  for (const auto& [id, image] : rec.images()) {
    if (!image.registered) {  // Bundler's marker of a camera it did not estimate
      out << "0 0 0\n0 0 0\n0 0 0\n0 0 0\n0 0 0\n";
      continue;
    }
    const Camera& camera = rec.camera(image.camera_id);
    if (const double deviation = BundlerModelDeviation(camera); deviation > 0.5) {
      ++num_approximated;
      worst_deviation = std::max(worst_deviation, deviation);
    }
    const Eigen::Matrix3d R = D * image.cam_from_world.R();
    const Eigen::Vector3d t = D * image.cam_from_world.translation;
    out << fmt::format("{} {} {}\n", camera.focal(), camera.params[Camera::kK1],
                       camera.params[Camera::kK2]);
    for (int r = 0; r < 3; ++r) out << fmt::format("{} {} {}\n", R(r, 0), R(r, 1), R(r, 2));
    out << fmt::format("{} {} {}\n", t.x(), t.y(), t.z());
  }
  // Information, not a warning: with the default intrinsics (a principal point estimated per
  // image size) nearly every model has an offset, and the COLMAP model beside it is exact.
  if (num_approximated > 0)
    info(
        "{}: {} cameras have an aspect ratio, skew or principal point offset (up to {:.1f} px) "
        "that Bundler's format cannot hold; written without it (the COLMAP model is exact)",
        file.string(), num_approximated, worst_deviation);
  fmt::memory_buffer buffer;  // one line at a time: see WriteImagesText (colmap_model.cc)
  for (const auto& [id, point] : rec.points3D()) {
    buffer.clear();
    auto it = std::back_inserter(buffer);
    fmt::format_to(it, "{} {} {}\n{} {} {}\n{}", point.xyz.x(), point.xyz.y(), point.xyz.z(),
                   point.color[0], point.color[1], point.color[2], point.track.size());
    for (const TrackElement& el : point.track) {
      const Image& image = rec.image(el.image_id);
      const Camera& camera = rec.camera(image.camera_id);
      const Eigen::Vector2d& xy = image.points2D.at(el.point2D_idx).xy;
      fmt::format_to(it, " {} {} {} {}", index.at(el.image_id), el.point2D_idx,
                     xy.x() - 0.5 * camera.width, 0.5 * camera.height - xy.y());
    }
    buffer.push_back('\n');
    out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
  }
}

}  // namespace

void WriteBundler(const Reconstruction& rec, const fs::path& bundle_file,
                  const fs::path& list_file) {
  WriteFileAtomically(bundle_file, [&](std::ostream& out) { WriteBundle(rec, out, bundle_file); });
  WriteFileAtomically(list_file, [&](std::ostream& out) { WriteList(rec, out); });
}

}  // namespace varsfm
