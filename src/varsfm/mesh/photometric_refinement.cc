#include "varsfm/mesh/photometric_refinement.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <opencv2/imgproc.hpp>

#include "varsfm/dense/window_warp.h"
#include "varsfm/geometry/rasterizer.h"
#include "varsfm/mesh/mesh_topology.h"
#include "varsfm/util/option_check.h"
#include "varsfm/util/progress.h"

namespace varsfm {

void PhotometricRefinementOptions::Check() const {
  CheckInRange("--photometric-refinement", iterations, 0, 10);
  CheckInRange("photometric refinement offsets", offsets, 1, 20);
  CheckPositive("photometric refinement step", step);
  CheckInRange("photometric refinement window radius", window_radius, 1, 10);
  CheckAtLeast("photometric refinement views", max_views, 2);
  CheckInRange("photometric refinement minimum views", min_views, 2, max_views);
  CheckInRange("photometric refinement minimum NCC", min_ncc, -1.0, 1.0);
  CheckNonNegative("photometric refinement NCC gain", min_ncc_gain);
  CheckFraction("photometric refinement minimum cosine", min_cos_angle);
  CheckPositive("photometric refinement depth tolerance", depth_tolerance);
}

RefinementView RefinementViewOf(const cv::Mat& photo, const PosedCamera& camera) {
  cv::Mat gray = photo;
  if (photo.channels() == 3) cv::cvtColor(photo, gray, cv::COLOR_BGR2GRAY);
  RefinementView view;
  gray.convertTo(view.gray, CV_32F, 1.0 / 255);
  view.camera = camera;
  return view;
}

namespace {

// Area-weighted vertex normals (the faces' cross products summed, faces counter-clockwise seen
// from outside); zero for a vertex in no face.
std::vector<Eigen::Vector3d> VertexNormals(const TriangleMesh& mesh) {
  std::vector<Eigen::Vector3d> normals(mesh.vertices.size(), Eigen::Vector3d::Zero());
  for (const Eigen::Vector3i& f : mesh.faces) {
    const Eigen::Vector3d& a = mesh.vertices[f[0]];
    const Eigen::Vector3d n = (mesh.vertices[f[1]] - a).cross(mesh.vertices[f[2]] - a);
    for (int k = 0; k < 3; ++k) normals[f[k]] += n;
  }
  for (Eigen::Vector3d& n : normals)
    if (n.squaredNorm() > 0) n.normalize();
  return normals;
}

// The views that see each vertex, most frontal first: `count` per vertex in slots of max_views.
struct VertexViews {
  int max_views = 0;
  std::vector<int> count;
  std::vector<float> cosine;
  std::vector<uint32_t> view;
};

// A vertex is seen by a view when it projects inside it, in front of (or on) the nearest face of
// the mesh's z-buffer there, and its normal makes an angle with the direction to the view's
// centre whose cosine is min_cos_angle or more. Appends (vertex, cosine) for each, in vertex
// order. `projected`: a buffer for the vertices' projections, reused from view to view.
void SeenInView(const RefinementView& view, const TriangleMesh& mesh,
                const std::vector<Eigen::Vector3d>& normals,
                const PhotometricRefinementOptions& options,
                std::vector<ProjectedVertex>* projected_buffer,
                std::vector<std::pair<uint32_t, float>>* seen) {
  const PosedCamera& camera = view.camera;
  const int width = view.gray.cols, height = view.gray.rows;
  ProjectVertices(mesh.vertices, camera.camera, camera.cam_from_world, 1.0, projected_buffer);
  const std::vector<ProjectedVertex>& projected = *projected_buffer;
  const FaceRaster raster = RasterizeFaces(projected, mesh.faces, width, height);
  const Eigen::Vector3d centre = camera.cam_from_world.Center();
  for (size_t i = 0; i < projected.size(); ++i) {
    const ProjectedVertex& p = projected[i];
    if (p.depth <= 0 || normals[i].squaredNorm() == 0) continue;
    const int x = static_cast<int>(std::floor(p.pixel.x()));
    const int y = static_cast<int>(std::floor(p.pixel.y()));
    if (x < 0 || y < 0 || x >= width || y >= height) continue;
    if (p.depth > raster.DepthAt(x, y) * (1 + options.depth_tolerance)) continue;
    // Either side: not every surface method orients its faces consistently (rasterizer.h).
    const float cosine =
        static_cast<float>(std::abs(normals[i].dot((centre - mesh.vertices[i]).normalized())));
    if (cosine >= options.min_cos_angle) seen->emplace_back(static_cast<uint32_t>(i), cosine);
  }
}

// Every vertex's max_views most frontal views (SeenInView). The views are drawn in parallel a
// batch at a time and offered to the vertices in view order, so that ties go to the earlier view
// whatever the thread count, and only one batch's lists are held at once. Ticks `progress` once
// per view.
VertexViews FindVertexViews(const std::vector<RefinementView>& views, const TriangleMesh& mesh,
                            const std::vector<Eigen::Vector3d>& normals,
                            const PhotometricRefinementOptions& options, Progress* progress) {
  const size_t n = mesh.vertices.size();
  VertexViews seen;
  seen.max_views = options.max_views;
  seen.count.assign(n, 0);
  seen.cosine.assign(n * options.max_views, 0.f);
  seen.view.assign(n * options.max_views, 0);
  // Keeps the vertex's slots sorted by cosine, the earlier view first among equals.
  const auto offer = [&](uint32_t i, uint32_t v, float cosine) {
    float* cos_slots = &seen.cosine[i * options.max_views];
    uint32_t* view_slots = &seen.view[i * options.max_views];
    int& count = seen.count[i];
    int k = std::min(count, options.max_views - 1);
    if (count == options.max_views && cos_slots[k] >= cosine) return;
    while (k > 0 && cos_slots[k - 1] < cosine) {
      cos_slots[k] = cos_slots[k - 1];
      view_slots[k] = view_slots[k - 1];
      --k;
    }
    cos_slots[k] = cosine;
    view_slots[k] = v;
    count = std::min(count + 1, options.max_views);
  };
  constexpr size_t kBatch = 8;
  std::vector<std::vector<std::pair<uint32_t, float>>> batch(kBatch);
  std::vector<std::vector<ProjectedVertex>> projected(kBatch);  // mesh-sized, kept per slot
  for (size_t first = 0; first < views.size(); first += kBatch) {
    const size_t last = std::min(views.size(), first + kBatch);
    tbb::parallel_for(first, last, [&](size_t v) {
      batch[v - first].clear();
      SeenInView(views[v], mesh, normals, options, &projected[v - first], &batch[v - first]);
      progress->Tick();
    });
    for (size_t v = first; v < last; ++v)
      for (const auto& [i, cosine] : batch[v - first]) offer(i, static_cast<uint32_t>(v), cosine);
  }
  return seen;
}

// Zero-mean NCC of two sample sets; NaN when either is flat.
double Ncc(const float* a, const float* b, size_t size) {
  const double m = static_cast<double>(size);
  double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
  for (size_t i = 0; i < size; ++i) {
    sa += a[i];
    sb += b[i];
    saa += a[i] * a[i];
    sbb += b[i] * b[i];
    sab += a[i] * b[i];
  }
  const double va = saa - sa * sa / m, vb = sbb - sb * sb / m;
  constexpr double kFlat = 1e-6;  // per sample, intensities in [0, 1]
  if (va < kFlat * m || vb < kFlat * m) return std::numeric_limits<double>::quiet_NaN();
  return (sab - sa * sb / m) / std::sqrt(va * vb);
}

// The offset along the normal at which one vertex's views agree best, where it was measured.
struct VertexOffset {
  double offset = 0;
  bool measured = false;
};

VertexOffset MeasureOffset(const std::vector<RefinementView>& views, const VertexViews& seen,
                           size_t vertex, const Eigen::Vector3d& point,
                           const Eigen::Vector3d& normal, double step_pixels,
                           const PhotometricRefinementOptions& options) {
  const int count = seen.count[vertex];
  if (count < options.min_views) return {};
  const uint32_t* view_ids = &seen.view[vertex * seen.max_views];
  const PosedCamera& reference = views[view_ids[0]].camera;
  const double depth = (reference.cam_from_world * point).z();
  const double pixel = depth / reference.camera.focal();  // one reference pixel at the vertex
  const double step = step_pixels * pixel;
  const Eigen::Vector3d u = normal.unitOrthogonal() * pixel;
  const Eigen::Vector3d w = normal.cross(u);
  const int r = options.window_radius, side = 2 * r + 1;
  const size_t samples = static_cast<size_t>(side) * side;

  const int num_offsets = 2 * options.offsets + 1;
  std::vector<double> score(num_offsets, std::numeric_limits<double>::quiet_NaN());
  // View j's samples at values[j * samples ...], refilled at each offset.
  std::vector<float> values(static_cast<size_t>(count) * samples);
  std::vector<uint8_t> inside(count);
  for (int k = 0; k < num_offsets; ++k) {
    const Eigen::Vector3d centre = point + (k - options.offsets) * step * normal;
    std::fill(inside.begin(), inside.end(), 1);
    for (int j = 0; j < count; ++j) {
      const RefinementView& view = views[view_ids[j]];
      const WarpSource source{view.gray.ptr<float>(), view.gray.cols, view.gray.rows};
      // The patch in the view's camera frame: its centre and its two sample steps.
      const Eigen::Vector3d c = view.camera.cam_from_world * centre;
      const Eigen::Vector3d du = view.camera.cam_from_world.rotation * u;
      const Eigen::Vector3d dw = view.camera.cam_from_world.rotation * w;
      size_t s = 0;
      for (int b = -r; b <= r && inside[j]; ++b)
        for (int a = -r; a <= r; ++a, ++s) {
          const Eigen::Vector3d in_camera = c + a * du + b * dw;
          if (in_camera.z() <= 0) {
            inside[j] = 0;
            break;
          }
          const Eigen::Vector2d p = view.camera.camera.Project(in_camera);
          if (p.x() < 0 || p.y() < 0 || p.x() > source.width || p.y() > source.height) {
            inside[j] = 0;
            break;
          }
          values[j * samples + s] =
              SampleBilinear(source, static_cast<float>(p.x()), static_cast<float>(p.y()));
        }
    }
    if (!inside[0]) continue;
    double sum = 0;
    int used = 0;
    for (int j = 1; j < count; ++j) {
      if (!inside[j]) continue;
      const double ncc = Ncc(&values[0], &values[j * samples], samples);
      if (std::isnan(ncc)) continue;
      sum += ncc;
      ++used;
    }
    if (used > 0) score[k] = sum / used;
  }
  int best = -1;
  for (int k = 0; k < num_offsets; ++k)
    if (!std::isnan(score[k]) && (best < 0 || score[k] > score[best])) best = k;
  const double here = score[options.offsets];
  // A best offset at the end of the range may lie beyond it: not measured (the next iteration
  // starts from where the neighbours moved it).
  if (best <= 0 || best + 1 >= num_offsets || std::isnan(here) || score[best] < options.min_ncc ||
      (best != options.offsets && score[best] < here + options.min_ncc_gain))
    return {};
  double sub = 0;  // the parabola through the best score and its neighbours
  if (!std::isnan(score[best - 1]) && !std::isnan(score[best + 1])) {
    const double curvature = score[best - 1] - 2 * score[best] + score[best + 1];
    if (curvature < 0)
      sub = std::clamp(0.5 * (score[best - 1] - score[best + 1]) / curvature, -0.5, 0.5);
  }
  return {(best - options.offsets + sub) * step, true};
}

}  // namespace

PhotometricRefinementStats RefinePhotometrically(const std::vector<RefinementView>& views,
                                                 const PhotometricRefinementOptions& options,
                                                 TriangleMesh* mesh) {
  PhotometricRefinementStats stats;
  if (options.iterations == 0 || views.size() < 2 || mesh->faces.empty()) return stats;
  const size_t n = mesh->vertices.size();
  const std::vector<std::vector<int>> neighbours = VertexNeighbours(*mesh);
  double total_offset = 0;
  // Per iteration, a tick per view's z-buffer and one per block of vertices measured.
  Progress progress("mesh: photometric refinement", 2 * views.size() * options.iterations);
  for (int iteration = 0; iteration < options.iterations; ++iteration) {
    const std::vector<Eigen::Vector3d> normals = VertexNormals(*mesh);
    progress.SetStatus(fmt::format("iteration {}: views", iteration + 1));
    const VertexViews seen = FindVertexViews(views, *mesh, normals, options, &progress);
    progress.SetStatus(fmt::format("iteration {}: offsets", iteration + 1));
    const double step_pixels = options.step / static_cast<double>(1 << iteration);
    std::vector<VertexOffset> measured(n);
    // In as many blocks of vertices as there are views, so that this half of an iteration
    // advances the progress as much as the z-buffers did.
    const size_t block = (n + views.size() - 1) / views.size();
    tbb::parallel_for(size_t{0}, views.size(), [&](size_t b) {
      for (size_t i = b * block; i < std::min(n, (b + 1) * block); ++i)
        measured[i] =
            MeasureOffset(views, seen, i, mesh->vertices[i], normals[i], step_pixels, options);
      progress.Tick();
    });
    // Each vertex's offset: the median of its own and its neighbours' measured offsets (robust to
    // one matched wrongly), then averaged with its neighbours' medians, so the moves vary smoothly
    // from vertex to vertex: medians alone vary in steps, which made the faces' orientations
    // noisy and cut the texture into many more charts.
    stats.measured_vertices = 0;
    std::vector<double> median(n, 0.0);
    std::vector<bool> has(n, false);
    std::vector<double> around;
    for (size_t i = 0; i < n; ++i) {
      if (measured[i].measured) ++stats.measured_vertices;
      around.clear();
      if (measured[i].measured) around.push_back(measured[i].offset);
      for (int j : neighbours[i])
        if (measured[j].measured) around.push_back(measured[j].offset);
      if (around.empty()) continue;
      const auto middle = around.begin() + around.size() / 2;
      std::nth_element(around.begin(), middle, around.end());
      median[i] = *middle;
      has[i] = true;
    }
    for (size_t i = 0; i < n; ++i) {
      if (!has[i]) continue;
      double sum = median[i];
      int count = 1;
      for (int j : neighbours[i])
        if (has[j]) sum += median[j], ++count;
      const double offset = sum / count;
      mesh->vertices[i] += offset * normals[i];
      total_offset += std::abs(offset);
    }
  }
  stats.mean_offset = total_offset / (static_cast<double>(n) * options.iterations);
  return stats;
}

}  // namespace varsfm
