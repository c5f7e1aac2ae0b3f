#include "varsfm/io/bundler.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>

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
  return std::hypot(p[Camera::kU0] - 0.5 * camera.width, p[Camera::kV0] - 0.5 * camera.height);
}

// Both writers fill `file`, a temporary; messages name `shown`, the file it becomes.
void WriteList(const Reconstruction& rec, const fs::path& file, const fs::path& shown) {
  std::ofstream out(file);
  if (!out) Fail("{}: cannot open for writing", shown.string());
  for (const auto& [id, image] : rec.images()) out << image.name << '\n';
  out.close();
  if (!out) Fail("{}: write failed", shown.string());
}

void WriteBundle(const Reconstruction& rec, const fs::path& file, const fs::path& shown) {
  std::map<image_t, int> index;  // image id -> Bundler camera index (0-based, list.txt order)
  for (const auto& [id, image] : rec.images()) index.emplace(id, static_cast<int>(index.size()));

  std::ofstream out(file);
  if (!out) Fail("{}: cannot open for writing", shown.string());
  out << "# Bundle file v0.3\n" << fmt::format("{} {}\n", index.size(), rec.points3D().size());
  const Eigen::Matrix3d D = Eigen::Vector3d(1, -1, -1).asDiagonal();
  size_t num_dropped = 0;
  double worst_deviation = 0.0;
  for (const auto& [id, image] : rec.images()) {
    if (!image.registered) {  // Bundler's marker of a camera it did not estimate
      out << "0 0 0\n0 0 0\n0 0 0\n0 0 0\n0 0 0\n";
      continue;
    }
    const Camera& camera = rec.camera(image.camera_id);
    if (const double deviation = BundlerModelDeviation(camera); deviation > 0.5) {
      ++num_dropped;
      worst_deviation = std::max(worst_deviation, deviation);
    }
    const Eigen::Matrix3d R = D * image.cam_from_world.R();
    const Eigen::Vector3d t = D * image.cam_from_world.translation;
    out << fmt::format("{} {} {}\n", camera.focal(), camera.params[Camera::kK1],
                       camera.params[Camera::kK2]);
    for (int r = 0; r < 3; ++r) out << fmt::format("{} {} {}\n", R(r, 0), R(r, 1), R(r, 2));
    out << fmt::format("{} {} {}\n", t.x(), t.y(), t.z());
  }
  if (num_dropped > 0)
    warn(
        "{}: {} cameras have an aspect ratio, skew or principal point offset (up to {:.1f} px) "
        "that Bundler's format cannot hold; they are dropped there (the COLMAP model keeps them)",
        shown.string(), num_dropped, worst_deviation);
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
  out.close();
  if (!out) Fail("{}: write failed", shown.string());
}

}  // namespace

void WriteBundler(const Reconstruction& rec, const fs::path& bundle_file,
                  const fs::path& list_file) {
  auto temp_of = [](const fs::path& f) {
    return f.parent_path() / fmt::format(".{}.tmp-{}", f.filename().string(), ::getpid());
  };
  const fs::path bundle_tmp = temp_of(bundle_file), list_tmp = temp_of(list_file);
  std::error_code ec;
  try {
    WriteBundle(rec, bundle_tmp, bundle_file);
    WriteList(rec, list_tmp, list_file);
    fs::rename(bundle_tmp, bundle_file);
    fs::rename(list_tmp, list_file);
  } catch (const fs::filesystem_error& e) {
    fs::remove(bundle_tmp, ec);
    fs::remove(list_tmp, ec);
    // A rename's path2 is the final file; path1 its temporary, which the user never sees.
    const fs::path& file = e.path2().empty() ? e.path1() : e.path2();
    Fail("{}: cannot write: {}", file.string(), e.code().message());
  } catch (...) {
    fs::remove(bundle_tmp, ec);
    fs::remove(list_tmp, ec);
    throw;
  }
}

}  // namespace varsfm
