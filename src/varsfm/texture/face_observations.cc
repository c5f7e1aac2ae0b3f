#include "varsfm/texture/face_observations.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <opencv2/imgproc.hpp>

#include "varsfm/camera/image_size.h"
#include "varsfm/geometry/rasterizer.h"
#include "varsfm/image/scratch_image.h"
#include "varsfm/util/error.h"
#include "varsfm/util/option_check.h"
#include "varsfm/util/progress.h"
#include "varsfm/util/scratch_memory.h"

namespace varsfm {
namespace {

// Sums over the raster pixels each face covers: gradient magnitude, colour, pixel count.
struct RasterSums {
  std::vector<float> gradient;
  std::vector<Eigen::Vector3f> colour;
  std::vector<int> pixels;
};

void SumOverFaces(const FaceRaster& raster, const cv::Mat& small, const cv::Mat& magnitude,
                  size_t num_faces, RasterSums* out) {
  RasterSums& sums = *out;
  sums.gradient.assign(num_faces, 0.0f);
  sums.colour.assign(num_faces, Eigen::Vector3f::Zero());
  sums.pixels.assign(num_faces, 0);
  for (int y = 0; y < raster.height; ++y) {
    const cv::Vec3f* c = small.ptr<cv::Vec3f>(y);
    const float* m = magnitude.ptr<float>(y);
    for (int x = 0; x < raster.width; ++x) {
      const int32_t f = raster.FaceAt(x, y);
      if (f < 0) continue;
      sums.gradient[f] += m[x];
      sums.colour[f] += Eigen::Vector3f(c[x][0], c[x][1], c[x][2]);
      ++sums.pixels[f];
    }
  }
}

// One thread's buffers for ObserveView, as large as the mesh, kept from view to view: fresh ones
// for every view were mostly page faults on a large mesh. ObserveView runs no parallel work while
// it uses them (OpenCV's, on TBB, comes before), so no other view's call can interleave on the
// thread and share them.
struct ViewScratch {
  std::vector<ProjectedVertex> full, projected;
  RasterSums sums;
};

// One view's observation of one face.
struct ViewObservation {
  uint32_t face;
  float quality;
  Eigen::Vector3f colour;
};

// View v's observations of the faces it may texture (in face order) and its coverage.
void ObserveView(const std::vector<Eigen::Vector3d>& vertices,
                 const std::vector<Eigen::Vector3i>& faces, const PosedCamera& view,
                 const cv::Mat& photo, const FaceObservationOptions& options, ViewScratch* scratch,
                 std::vector<ViewObservation>* seen, double* coverage, cv::Mat* small_out,
                 double* scale_out) {
  const Camera& camera = view.camera;
  const ScaledSize size = SizeWithin(camera, options.max_raster_size);
  const double scale = size.scale;
  const int w = size.width, h = size.height;
  cv::Mat small8, small, grey, gx, gy, magnitude;
  cv::resize(photo, small8, cv::Size(w, h), 0, 0, cv::INTER_AREA);
  small8.convertTo(small, CV_32FC3);
  cv::cvtColor(small, grey, cv::COLOR_BGR2GRAY);
  // Sobel's 3x3 kernel sums 4 differences over 2 pixels: /8 gives grey levels per pixel.
  cv::Sobel(grey, gx, CV_32F, 1, 0, 3, 1.0 / 8);
  cv::Sobel(grey, gy, CV_32F, 0, 1, 3, 1.0 / 8);
  cv::magnitude(gx, gy, magnitude);
  magnitude += options.gradient_floor;

  std::vector<ProjectedVertex>& full = scratch->full;
  std::vector<ProjectedVertex>& projected = scratch->projected;
  ProjectVertices(vertices, camera, view.cam_from_world, 1.0, &full);
  projected = full;
  for (ProjectedVertex& v : projected) v.pixel *= scale;
  const FaceRaster raster = RasterizeFaces(projected, faces, w, h);
  *coverage = static_cast<double>(std::count_if(raster.face.begin(), raster.face.end(),
                                                [](int32_t f) { return f >= 0; })) /
              raster.face.size();
  SumOverFaces(raster, small, magnitude, faces.size(), &scratch->sums);
  const RasterSums& sums = scratch->sums;
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
  const auto inside = [&](const Eigen::Vector2d& q) {
    const double border = options.border_px;
    return q.x() >= border && q.y() >= border && q.x() <= camera.width - border &&
           q.y() <= camera.height - border;
  };

  const Eigen::Matrix3d R = view.cam_from_world.R();
  const Eigen::Vector3d& t = view.cam_from_world.translation;
  const Eigen::Vector3d centre = view.cam_from_world.Center();
  for (size_t f = 0; f < faces.size(); ++f) {
    const ProjectedVertex* p[3] = {&projected[faces[f][0]], &projected[faces[f][1]],
                                   &projected[faces[f][2]]};
    if (p[0]->depth <= 0 || p[1]->depth <= 0 || p[2]->depth <= 0) continue;
    // A face cut by the image border can still be textured (its outside part gets the border
    // pixels repeated), but any view that sees it whole is much preferred.
    double weight = 1.0;
    const Eigen::Vector2d* q[3] = {&full[faces[f][0]].pixel, &full[faces[f][1]].pixel,
                                   &full[faces[f][2]].pixel};
    if (!inside(*q[0]) || !inside(*q[1]) || !inside(*q[2])) {
      if (!inside((*q[0] + *q[1] + *q[2]) / 3)) continue;
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
    const Eigen::Vector2d centroid_pixel = camera.Project(x) * scale;
    bool visible = unoccluded(centroid_pixel, x.z());
    for (int k = 0; k < 3 && visible; ++k) {
      const Eigen::Vector2d& s = p[k]->pixel;
      if (s.x() < 0 || s.y() < 0 || s.x() >= w || s.y() >= h) continue;  // cut by the border
      visible = unoccluded(s, p[k]->depth);
    }
    if (!visible) continue;
    // Waechter et al.: faces smaller than a pixel take the gradient and colour at their centroid
    // times their area. Quality in full-resolution pixel units, so views of different sizes
    // compare.
    const Eigen::Vector2d e1 = p[1]->pixel - p[0]->pixel, e2 = p[2]->pixel - p[0]->pixel;
    const double area = 0.5 * std::abs(e1.x() * e2.y() - e1.y() * e2.x());
    double gradient_sum;
    Eigen::Vector3f colour;
    if (sums.pixels[f] > 0) {
      gradient_sum = sums.gradient[f];
      colour = sums.colour[f] / static_cast<float>(sums.pixels[f]);
    } else {
      const int cx = std::clamp(static_cast<int>(centroid_pixel.x()), 0, w - 1);
      const int cy = std::clamp(static_cast<int>(centroid_pixel.y()), 0, h - 1);
      gradient_sum = std::max(1.0, area) * magnitude.at<float>(cy, cx);
      colour = SampleBilinear(small, centroid_pixel);
    }
    float quality = static_cast<float>(weight * gradient_sum / (scale * scale));
    if (quality <= 0) quality = std::numeric_limits<float>::min();
    seen->push_back({static_cast<uint32_t>(f), quality, colour});
  }
  seen->shrink_to_fit();  // every view's list is held until all are gathered
  *small_out =
      options.scratch_folder.empty() ? small : CopyToScratch(small, options.scratch_folder);
  *scale_out = scale;
}

// Every face's best views so far, at most `stride` of them, in fixed slots: offered in view
// order, a face's views stay in view order until a better one replaces its worst.
class BestViewsPerFace {
 public:
  BestViewsPerFace(size_t num_faces, size_t stride)
      : stride_(stride),
        view_(num_faces * stride),
        quality_(num_faces * stride),
        colour_(num_faces * stride),
        count_(num_faces, 0) {}

  void Offer(size_t face, size_t view, float quality, const Eigen::Vector3f& colour) {
    const size_t base = face * stride_;
    size_t slot = base + count_[face];
    if (count_[face] < stride_) {
      ++count_[face];
    } else {
      // The worst kept: the lowest quality, of those the latest view. `view` comes after every
      // kept one, so it loses a tie.
      size_t worst = base;
      for (size_t k = base + 1; k < base + stride_; ++k)
        if (quality_[k] < quality_[worst] ||
            (quality_[k] == quality_[worst] && view_[k] > view_[worst]))
          worst = k;
      if (!(quality > quality_[worst])) return;
      slot = worst;
    }
    view_[slot] = static_cast<uint32_t>(view);
    quality_[slot] = quality;
    colour_[slot] = colour;
  }

  // Face by face, in view order.
  void MoveTo(FaceObservations* obs) {
    const size_t num_faces = count_.size();
    obs->begin.assign(num_faces + 1, 0);
    for (size_t f = 0; f < num_faces; ++f) obs->begin[f + 1] = obs->begin[f] + count_[f];
    const size_t total = obs->begin[num_faces];
    obs->view.resize(total);
    obs->quality.resize(total);
    obs->colour.resize(total);
    obs->deviation.assign(total, 0.0f);
    std::vector<size_t> order;
    for (size_t f = 0; f < num_faces; ++f) {
      const size_t base = f * stride_;
      order.resize(count_[f]);
      for (size_t k = 0; k < order.size(); ++k) order[k] = base + k;
      std::sort(order.begin(), order.end(),
                [&](size_t a, size_t b) { return view_[a] < view_[b]; });
      for (size_t k = 0; k < order.size(); ++k) {
        const size_t to = obs->begin[f] + k;
        obs->view[to] = view_[order[k]];
        obs->quality[to] = quality_[order[k]];
        obs->colour[to] = colour_[order[k]];
      }
    }
  }

 private:
  size_t stride_;
  std::vector<uint32_t> view_;
  std::vector<float> quality_;
  std::vector<Eigen::Vector3f> colour_;
  std::vector<uint32_t> count_;
};

}  // namespace

Eigen::Vector3f SampleBilinear(const cv::Mat& image, const Eigen::Vector2d& p) {
  const double x = std::clamp(p.x() - 0.5, 0.0, image.cols - 1.0);
  const double y = std::clamp(p.y() - 0.5, 0.0, image.rows - 1.0);
  const int x0 = std::min(static_cast<int>(x), image.cols - 1);
  const int y0 = std::min(static_cast<int>(y), image.rows - 1);
  const int x1 = std::min(x0 + 1, image.cols - 1), y1 = std::min(y0 + 1, image.rows - 1);
  const float fx = static_cast<float>(x - x0), fy = static_cast<float>(y - y0);
  const auto at = [&](int xx, int yy) {
    const cv::Vec3f& c = image.at<cv::Vec3f>(yy, xx);
    return Eigen::Vector3f(c[0], c[1], c[2]);
  };
  return (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x1, y0)) +
         fy * ((1 - fx) * at(x0, y1) + fx * at(x1, y1));
}

FaceObservations ObserveFaces(const std::vector<Eigen::Vector3d>& vertices,
                              const std::vector<Eigen::Vector3i>& faces,
                              const std::vector<PosedCamera>& views,
                              const std::function<cv::Mat(size_t)>& load_image,
                              const FaceObservationOptions& options) {
  FaceObservations obs;
  obs.num_faces = faces.size();
  obs.num_views = views.size();
  obs.coverage.assign(obs.num_views, 0.0);
  obs.small_photos.resize(obs.num_views);
  obs.small_scale.assign(obs.num_views, 1.0);
  // A folder that cannot hold scratch memory leaves the small photos on the heap, said once here
  // (the allocator would fall back to the heap without a word for each photo).
  FaceObservationOptions view_options = options;
  if (!options.scratch_folder.empty() &&
      !ScratchFolderUsable(options.scratch_folder, "the views' small photos"))
    view_options.scratch_folder.clear();
  BestViewsPerFace best(obs.num_faces, std::min<size_t>(options.max_views_per_face, obs.num_views));
  tbb::task_arena arena(options.num_threads > 0 ? options.num_threads : tbb::task_arena::automatic);
  Progress progress("texture: visibility", obs.num_views);
  // Views in batches, each batch's observations merged in view order before the next is
  // observed: only one batch's lists are held beside the faces' best views.
  constexpr size_t kBatch = 32;
  std::vector<std::vector<ViewObservation>> seen(kBatch);
  tbb::enumerable_thread_specific<ViewScratch> scratch;
  for (size_t first = 0; first < obs.num_views; first += kBatch) {
    const size_t last = std::min(obs.num_views, first + kBatch);
    arena.execute([&] {
      tbb::parallel_for(first, last, [&](size_t v) {
        const cv::Mat photo = load_image(v);
        const Camera& camera = views[v].camera;
        if (photo.cols != camera.width || photo.rows != camera.height || photo.type() != CV_8UC3)
          Fail("texture: photo {} is {}x{} (type {}) but its camera is {}x{}", v, photo.cols,
               photo.rows, photo.type(), camera.width, camera.height);
        ObserveView(vertices, faces, views[v], photo, view_options, &scratch.local(),
                    &seen[v - first], &obs.coverage[v], &obs.small_photos[v], &obs.small_scale[v]);
        progress.Tick();
      });
    });
    for (size_t v = first; v < last; ++v) {
      for (const ViewObservation& o : seen[v - first]) best.Offer(o.face, v, o.quality, o.colour);
      std::vector<ViewObservation>().swap(seen[v - first]);
    }
  }
  progress.Finish();
  best.MoveTo(&obs);
  return obs;
}

size_t FaceObservations::Find(size_t v, size_t face) const {
  const auto first = view.begin() + begin[face], last = view.begin() + begin[face + 1];
  const auto it = std::lower_bound(first, last, static_cast<uint32_t>(v));
  return it != last && *it == v ? static_cast<size_t>(it - view.begin()) : kNone;
}

void FaceObservationOptions::Check() const {
  CheckAtLeast("max_raster_size", max_raster_size, 16);
  CheckFraction("--depth-tolerance", depth_tolerance);
  CheckFraction("--min-cos", min_cos_angle);
  CheckNonNegative("border_px", border_px);
  CheckFraction("partial_face_weight", partial_face_weight);
  CheckNonNegative("gradient_floor", gradient_floor);
  CheckAtLeast("max_views_per_face", max_views_per_face, 1);
  CheckNonNegative("--threads", num_threads);
}

}  // namespace varsfm
