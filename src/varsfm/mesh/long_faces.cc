#include "varsfm/mesh/long_faces.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>

#include "varsfm/camera/image_size.h"
#include "varsfm/geometry/rasterizer.h"
#include "varsfm/util/option_check.h"

namespace varsfm {
namespace {

// Per face: whether an edge is longer than factor x the median edge length.
std::vector<bool> FindLongFaces(double factor, const TriangleMesh& mesh) {
  std::vector<double> longest(mesh.faces.size());
  for (size_t i = 0; i < mesh.faces.size(); ++i) {
    const Eigen::Vector3i& f = mesh.faces[i];
    const Eigen::Vector3d &a = mesh.vertices[f[0]], &b = mesh.vertices[f[1]],
                          &c = mesh.vertices[f[2]];
    longest[i] = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  }
  std::vector<double> sorted = longest;
  const auto middle = sorted.begin() + static_cast<ptrdiff_t>(sorted.size() / 2);
  std::nth_element(sorted.begin(), middle, sorted.end());
  const double limit = factor * factor * *middle;  // squared lengths
  std::vector<bool> is_long(mesh.faces.size());
  for (size_t i = 0; i < longest.size(); ++i) is_long[i] = longest[i] > limit;
  return is_long;
}

// What the views say of the long faces: seen in an enclosed hole by some view, seen reaching
// the open by some view. Flags that views set in any order (a union: deterministic), one byte a
// face whatever the number of views.
struct Verdicts {
  explicit Verdicts(size_t faces) : enclosed(faces), open(faces) {}
  std::vector<std::atomic<uint8_t>> enclosed, open;
};

// The connected regions (4-neighbours, no step in depth above max_depth_ratio) of pixels whose
// nearest face is long, each judged by the pixels around it (8-neighbours): enclosed when none
// is outside the image and enough show a kept face no farther than max_depth_ratio x the
// region's pixel beside them.
void JudgeView(const LongFaceOptions& options, const PosedCamera& view,
               const std::vector<bool>& is_long, const TriangleMesh& mesh, Verdicts* verdicts) {
  const ScaledSize size = SizeWithin(view.camera, options.raster_size);
  const int width = size.width, height = size.height;
  const FaceRaster raster =
      RasterizeFaces(ProjectVertices(mesh.vertices, view.camera, view.cam_from_world, size.scale),
                     mesh.faces, width, height);
  const auto at = [&](int x, int y) { return static_cast<size_t>(y) * width + x; };
  const auto long_pixel = [&](size_t p) { return raster.face[p] >= 0 && is_long[raster.face[p]]; };
  // A region is one patch of surface: long faces behind one another in the image (a membrane in
  // front of the background's) are judged apart.
  const auto depth_step = [&](size_t p, size_t q) {
    const float dp = raster.depth[p], dq = raster.depth[q];
    return dq > options.max_depth_ratio * dp || dp > options.max_depth_ratio * dq;
  };

  std::vector<int32_t> region(raster.face.size(), -1);
  std::vector<size_t> stack, pixels;
  int32_t regions = 0;
  for (size_t seed = 0; seed < raster.face.size(); ++seed) {
    if (region[seed] >= 0 || !long_pixel(seed)) continue;
    const int32_t id = regions++;
    region[seed] = id;
    stack.assign(1, seed);
    pixels.clear();
    while (!stack.empty()) {
      const size_t p = stack.back();
      stack.pop_back();
      pixels.push_back(p);
      const int x = static_cast<int>(p % width), y = static_cast<int>(p / width);
      for (const auto& [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
        const int u = x + dx, v = y + dy;
        if (u < 0 || v < 0 || u >= width || v >= height) continue;
        const size_t q = at(u, v);
        if (region[q] < 0 && long_pixel(q) && !depth_step(p, q)) {
          region[q] = id;
          stack.push_back(q);
        }
      }
    }
    bool reaches_edge = false;
    size_t around = 0, enclosing = 0;
    for (const size_t p : pixels) {
      const int x = static_cast<int>(p % width), y = static_cast<int>(p / width);
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int u = x + dx, v = y + dy;
          if (u < 0 || v < 0 || u >= width || v >= height) {
            reaches_edge = true;
            continue;
          }
          const size_t q = at(u, v);
          if (region[q] == id) continue;
          ++around;
          enclosing += raster.face[q] >= 0 && !is_long[raster.face[q]] &&
                       raster.depth[q] <= options.max_depth_ratio * raster.depth[p];
        }
    }
    const bool enclosed =
        !reaches_edge && around > 0 && enclosing >= options.min_enclosed_fraction * around;
    std::vector<std::atomic<uint8_t>>& mark = enclosed ? verdicts->enclosed : verdicts->open;
    for (const size_t p : pixels) mark[raster.face[p]].store(1, std::memory_order_relaxed);
  }
}

}  // namespace

void LongFaceOptions::Check() const {
  CheckNonNegative("--max-edge-factor", max_edge_factor);
  CheckAtLeast("long-face raster size", raster_size, 16);
  CheckAtLeast("long-face depth ratio", max_depth_ratio, 1.0);
  CheckFraction("long-face enclosed fraction", min_enclosed_fraction);
}

LongFaceStats RemoveLongFaces(const LongFaceOptions& options, const std::vector<PosedCamera>& views,
                              TriangleMesh* mesh) {
  LongFaceStats stats;
  if (options.max_edge_factor <= 0 || mesh->faces.empty()) return stats;
  const std::vector<bool> is_long = FindLongFaces(options.max_edge_factor, *mesh);
  stats.long_faces = static_cast<size_t>(std::count(is_long.begin(), is_long.end(), true));
  if (stats.long_faces == 0) return stats;

  std::vector<bool> keep(is_long.size(), false);
  if (options.keep_enclosed && !views.empty()) {
    Verdicts verdicts(is_long.size());
    tbb::parallel_for(size_t{0}, views.size(),
                      [&](size_t v) { JudgeView(options, views[v], is_long, *mesh, &verdicts); });
    // Kept: enclosed in some view, and open in none (a membrane a view happens to see framed,
    // e.g. the sky through an arch, reaches the open in another).
    for (size_t f = 0; f < is_long.size(); ++f)
      keep[f] = verdicts.enclosed[f].load() && !verdicts.open[f].load();
  }
  size_t kept = 0;
  for (size_t f = 0; f < is_long.size(); ++f) {
    if (is_long[f] && !keep[f]) continue;
    stats.kept += is_long[f];
    mesh->faces[kept++] = mesh->faces[f];
  }
  mesh->faces.resize(kept);
  return stats;
}

}  // namespace varsfm
