#pragma once
// What every view sees of every face: whether it sees it unoccluded and well inside the image,
// how well (the quality of Waechter, Moehrle & Goesele, "Let there be color!", ECCV 2014,
// sec. 3.1: the gradient magnitude integrated over the face's projection, which rewards near,
// frontal and sharp views alike), and the face's mean colour there, for the photo-consistency
// check and the exposure gains. Each view also keeps a small copy of its photo for sampling
// colours along seams (colour_levelling.h).
#include <cstdint>
#include <filesystem>
#include <functional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "varsfm/geometry/posed_camera.h"

namespace varsfm {

struct FaceObservationOptions {
  // A view's small photo, 3 floats a raster pixel.
  static constexpr size_t kSmallPhotoBytesPerPixel = 12;

  // Visibility rasters and the photos' small copies are at most this many pixels on their
  // longer side (speed; faces are tested at their corners and centroid, so faces smaller than a
  // raster pixel still are).
  int max_raster_size = 1000;
  // A face is occluded when the raster is nearer than its centroid or one of its corners by more
  // than this fraction of the depth.
  double depth_tolerance = 0.01;
  // Faces seen at more than acos(min_cos_angle) from their normal are not textured from the view.
  double min_cos_angle = 0.15;
  // Vertices should project this far inside the image so the chart's pixels all exist.
  double border_px = 2.0;
  // Quality factor for a face only partly inside the image (its centroid must be inside).
  double partial_face_weight = 0.05;
  // Added to the gradient magnitude (grey levels per pixel) before integrating: among views of
  // a weakly textured face the one that sees it largest wins, and sharpness decides only where
  // the gradient is strong (a low floor, letting sharpness decide everywhere, rendered held-out
  // views no better: the texture labelling-and-levelling results in bench/results).
  double gradient_floor = 20.0;
  // Each face keeps its best this many views (by quality; ties: the earlier view). On a large
  // capture a face is seen by dozens of photos, and a record of every view of every face grew
  // with the photos times the faces (1000 photos: 20 GB); selection and the consistency check
  // need a few good views, not all of them.
  int max_views_per_face = 16;
  int num_threads = 0;  // 0: all cores
  // Where the views' small photos (held for the levelling, kSmallPhotoBytesPerPixel a raster
  // pixel: 9 MB a view at 1000 px) are kept: scratch memory in this folder (image/scratch_image.h),
  // which the kernel may write out under memory pressure; empty, or a folder with no room: the
  // heap. The same result either way. `varsfm texture` sets it where the views would not fit easily
  // (pipeline/scratch_choice.h).
  std::filesystem::path scratch_folder;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

struct FaceObservations {
  size_t num_faces = 0;
  size_t num_views = 0;
  // The views that may texture each face (at most max_views_per_face), face by face and in view
  // order: face f's entries are [begin[f], begin[f + 1]). Sparse, as a view sees a part of a
  // large model: a table of every view and face grew with the views times the faces
  // (docs/measurements.md).
  std::vector<size_t> begin;  // num_faces + 1
  std::vector<uint32_t> view;
  std::vector<float> quality;  // > 0 when observed; 0 once photo-consistency rejects the view
  std::vector<Eigen::Vector3f> colour;  // BGR, 0-255, the mean over the face's projection
  // The colour's distance from the consensus of the face's views (photo_consistency.h), after
  // the exposure gains, in grey levels; 0 where no consensus was found (or not computed).
  std::vector<float> deviation;
  std::vector<double> coverage;       // per view: the fraction of its pixels the mesh covers
  std::vector<cv::Mat> small_photos;  // per view: CV_32FC3 BGR, small_scale x the photo
  std::vector<double> small_scale;

  static constexpr size_t kNone = static_cast<size_t>(-1);
  // The entry of `view`'s observation of `face`, or kNone.
  size_t Find(size_t view, size_t face) const;
  float Quality(size_t v, size_t face) const {
    const size_t k = Find(v, face);
    return k == kNone ? 0.0f : quality[k];
  }
  Eigen::Vector3f Colour(size_t v, size_t face) const {
    const size_t k = Find(v, face);
    return k == kNone ? Eigen::Vector3f::Zero() : colour[k];
  }
};

// `load_image(v)` returns view v's photo (BGR, 8-bit, the camera's size); throws varsfm::Error
// for a photo of another size.
FaceObservations ObserveFaces(const std::vector<Eigen::Vector3d>& vertices,
                              const std::vector<Eigen::Vector3i>& faces,
                              const std::vector<PosedCamera>& views,
                              const std::function<cv::Mat(size_t)>& load_image,
                              const FaceObservationOptions& options = {});

// Bilinear sample of a CV_32FC3 image at pixel position p (top-left-corner convention: pixel
// (x, y) covers [x, x+1) x [y, y+1)), clamped to the image.
Eigen::Vector3f SampleBilinear(const cv::Mat& image, const Eigen::Vector2d& p);

}  // namespace varsfm
