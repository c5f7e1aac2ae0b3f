#include "varsfm/texture/view_selection.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "varsfm/texture/face_adjacency.h"
#include "varsfm/texture/rasterizer.h"
#include "varsfm/util/option_check.h"
#include "varsfm/util/progress.h"

namespace varsfm {
namespace {

// Scores of every face in one view: projected area in full-resolution pixels where the face is
// visible and well inside the image, 0 otherwise. `coverage`: the fraction of the view's
// pixels the mesh covers.
void ScoreView(const std::vector<Eigen::Vector3d>& vertices,
               const std::vector<Eigen::Vector3i>& faces, const TextureView& view,
               const ViewSelectionOptions& options, float* scores /* stride: 1 per face */,
               double* coverage) {
  const Camera& camera = view.camera;
  const double scale = std::min(
      1.0, options.max_raster_size / static_cast<double>(std::max(camera.width, camera.height)));
  const int w = std::max(1, static_cast<int>(std::lround(camera.width * scale)));
  const int h = std::max(1, static_cast<int>(std::lround(camera.height * scale)));
  const std::vector<ProjectedVertex> full = ProjectVertices(vertices, camera, view.cam_from_world);
  std::vector<ProjectedVertex> small = full;
  for (ProjectedVertex& v : small) v.pixel *= scale;
  const FaceRaster raster = RasterizeFaces(small, faces, w, h);
  *coverage = static_cast<double>(std::count_if(raster.face.begin(), raster.face.end(),
                                                [](int32_t f) { return f >= 0; })) /
              raster.face.size();
  // A point passes the depth test when the nearest surface around its raster pixel (the farthest
  // of a 3x3 neighbourhood, so points on an occluder's silhouette are not lost to rounding) is
  // not clearly in front of it.
  const auto unoccluded = [&](const Eigen::Vector2d& pixel, double depth) {
    const int px = static_cast<int>(std::floor(pixel.x())),
              py = static_cast<int>(std::floor(pixel.y()));
    float farthest = 0;
    for (int y = std::max(0, py - 1); y <= std::min(h - 1, py + 1); ++y)
      for (int x = std::max(0, px - 1); x <= std::min(w - 1, px + 1); ++x)
        farthest = std::max(farthest, raster.DepthAt(x, y));
    return depth <= farthest * (1 + options.depth_tolerance);
  };

  const Eigen::Matrix3d R = view.cam_from_world.R();
  const Eigen::Vector3d& t = view.cam_from_world.translation;
  const Eigen::Vector3d centre = view.cam_from_world.Center();
  const double border = options.border_px;
  for (size_t f = 0; f < faces.size(); ++f) {
    scores[f] = 0;
    const ProjectedVertex* p[3] = {&full[faces[f][0]], &full[faces[f][1]], &full[faces[f][2]]};
    if (p[0]->depth <= 0 || p[1]->depth <= 0 || p[2]->depth <= 0) continue;
    const auto inside = [&](const Eigen::Vector2d& q) {
      return q.x() >= border && q.y() >= border && q.x() <= camera.width - border &&
             q.y() <= camera.height - border;
    };
    // A face cut by the image border can still be textured (its outside part gets the border
    // pixels repeated), but any view that sees it whole is much preferred.
    double weight = 1.0;
    if (!inside(p[0]->pixel) || !inside(p[1]->pixel) || !inside(p[2]->pixel)) {
      if (!inside((p[0]->pixel + p[1]->pixel + p[2]->pixel) / 3)) continue;
      weight = options.partial_face_weight;
    }
    const Eigen::Vector3d& a = vertices[faces[f][0]];
    const Eigen::Vector3d& b = vertices[faces[f][1]];
    const Eigen::Vector3d& c = vertices[faces[f][2]];
    const Eigen::Vector3d normal = (b - a).cross(c - a);
    const Eigen::Vector3d centroid = (a + b + c) / 3;
    const Eigen::Vector3d to_camera = centre - centroid;
    const double norms = normal.norm() * to_camera.norm();
    if (norms <= 0 || std::abs(normal.dot(to_camera)) < options.min_cos_angle * norms) continue;
    // Visible when its centroid and all three corners pass the depth test: a face partly hidden
    // (say, behind the silhouette of a nearer object) would otherwise carry the occluder's colour.
    const Eigen::Vector3d x = R * centroid + t;
    bool visible = unoccluded(camera.Project(x) * scale, x.z());
    for (int k = 0; k < 3 && visible; ++k) {
      const Eigen::Vector2d q = p[k]->pixel * scale;
      if (q.x() < 0 || q.y() < 0 || q.x() >= w || q.y() >= h) continue;  // cut by the border
      visible = unoccluded(q, p[k]->depth);
    }
    if (!visible) continue;
    const Eigen::Vector2d e1 = p[1]->pixel - p[0]->pixel, e2 = p[2]->pixel - p[0]->pixel;
    scores[f] = static_cast<float>(weight * 0.5 * std::abs(e1.x() * e2.y() - e1.y() * e2.x()));
    if (scores[f] <= 0) scores[f] = std::numeric_limits<float>::min();  // visible, sub-pixel
  }
}

}  // namespace

ViewSelection SelectViews(const std::vector<Eigen::Vector3d>& vertices,
                          const std::vector<Eigen::Vector3i>& faces,
                          const std::vector<TextureView>& views,
                          const ViewSelectionOptions& options) {
  const size_t num_faces = faces.size(), num_views = views.size();
  // View-major so each view's task writes one contiguous block.
  std::vector<float> scores(num_faces * num_views, 0.0f);
  ViewSelection selection;
  selection.coverage.assign(num_views, 0.0);
  tbb::task_arena arena(options.num_threads > 0 ? options.num_threads : tbb::task_arena::automatic);
  Progress progress("texture: visibility", num_views);
  arena.execute([&] {
    tbb::parallel_for(size_t{0}, num_views, [&](size_t v) {
      ScoreView(vertices, faces, views[v], options, scores.data() + v * num_faces,
                &selection.coverage[v]);
      progress.Tick();
    });
  });
  progress.Finish();

  selection.labels.assign(num_faces, -1);
  std::vector<float> best(num_faces, 0.0f);
  for (size_t f = 0; f < num_faces; ++f) {
    for (size_t v = 0; v < num_views; ++v) {
      if (scores[v * num_faces + f] > best[f]) {
        best[f] = scores[v * num_faces + f];
        selection.labels[f] = static_cast<int>(v);
      }
    }
    if (selection.labels[f] >= 0) ++selection.num_visible_faces;
  }

  // Potts smoothing by iterated conditional modes (Besag 1986): each face in turn takes the
  // label minimising its data cost plus smoothness x (labelled neighbours that disagree).
  const std::vector<std::array<int, 3>> neighbours = FaceNeighbours(faces);
  const std::vector<int> initial = selection.labels;
  for (int iter = 0; iter < options.smoothing_iterations; ++iter) {
    size_t changed = 0;
    for (size_t f = 0; f < num_faces; ++f) {
      if (selection.labels[f] < 0) continue;
      const auto cost = [&](int label) {
        double c = 1.0 - scores[label * num_faces + f] / best[f];
        for (const int g : neighbours[f])
          if (g >= 0 && selection.labels[g] >= 0 && selection.labels[g] != label)
            c += options.smoothness;
        return c;
      };
      int best_label = selection.labels[f];
      double best_cost = cost(best_label);
      // Only labels the face can take and its neighbours hold are worth trying.
      for (const int g : neighbours[f]) {
        if (g < 0) continue;
        const int label = selection.labels[g];
        if (label < 0 || label == best_label || scores[label * num_faces + f] <= 0) continue;
        const double c = cost(label);
        if (c < best_cost) {
          best_cost = c;
          best_label = label;
        }
      }
      if (best_label != selection.labels[f]) {
        selection.labels[f] = best_label;
        ++changed;
      }
    }
    if (changed == 0) break;
  }
  for (size_t f = 0; f < num_faces; ++f)
    selection.num_changed_by_smoothing += selection.labels[f] != initial[f];
  return selection;
}

void ViewSelectionOptions::Check() const {
  CheckAtLeast("max_raster_size", max_raster_size, 16);
  CheckInRange("--depth-tolerance", depth_tolerance, 0, 1);
  CheckInRange("--min-cos", min_cos_angle, 0, 1);
  CheckAtLeast("border_px", border_px, 0);
  CheckInRange("partial_face_weight", partial_face_weight, 0, 1);
  CheckAtLeast("--smoothness", smoothness, 0);
  CheckAtLeast("smoothing_iterations", smoothing_iterations, 0);
  CheckAtLeast("--threads", num_threads, 0);
}

}  // namespace varsfm
