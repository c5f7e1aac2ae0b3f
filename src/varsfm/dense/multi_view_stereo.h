#pragma once
// Multi-view stereo by depth maps: every registered view that has source views (source_views.h)
// and is not redundant with the others (reference_views.h) gets a PatchMatch depth and normal map
// (patchmatch.h) at a capped resolution, started from the sparse points it observes and,
// optionally, a prior point cloud (match propagation's); the maps are filtered by geometric
// consistency and fused into a point cloud with normals and visibility (depth_fusion.h).
#include <filesystem>
#include <functional>

#include <opencv2/core.hpp>

#include "varsfm/dense/depth_edges.h"
#include "varsfm/dense/depth_fusion.h"
#include "varsfm/dense/patchmatch.h"
#include "varsfm/dense/planar_prior.h"
#include "varsfm/dense/reference_views.h"
#include "varsfm/dense/source_views.h"
#include "varsfm/scene/point_cloud.h"
#include "varsfm/scene/reconstruction.h"
#include "varsfm/util/random.h"

namespace varsfm {

struct MultiViewStereoOptions {
  // What a view holds until fusion, a pixel at max_image_size: its colour (3 bytes) and grey
  // (4) photo, then its depth (4), normal (12) and cost (4) maps.
  static constexpr size_t kViewBytesPerPixel = 27;

  // Depth maps are computed at most this size (longer side, px); larger photos are downscaled.
  // On held-out views a larger map gains PSNR and loses coverage (the NCC window is a fixed
  // number of pixels, so it spans less of a weakly textured surface), for time that grows with
  // the pixels (docs/measurements.md, "The depth maps at 800 px").
  int max_image_size = 800;
  ReferenceViewOptions references;  // which views get a depth map
  SourceViewOptions sources;
  PatchMatchOptions patchmatch;
  // A last pass with the planar prior of each view's confident, consistent depths (0 iterations:
  // none).
  PlanarPriorOptions planar;
  DepthEdgeOptions edges;  // before fusion
  DepthFusionOptions fusion;
  uint64_t seed = kDefaultSeed;
  // Where every view's photo and depth map are kept once made: scratch memory in this folder
  // (util/scratch_memory.h), which the kernel may write out and drop when RAM runs short, so
  // that the views together may outgrow RAM (kViewBytesPerPixel: ~13 MB a view at 800 px).
  // Empty: the heap, as is whatever the folder has no room for (with a warning). The same result
  // either way. `varsfm densify` sets it where the views would not fit easily
  // (pipeline/scratch_choice.h).
  std::filesystem::path scratch_folder;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

struct MultiViewStereoStats {
  size_t num_views = 0;              // reference views with a depth map
  size_t num_redundant_views = 0;    // views left without one as redundant (reference_views.h)
  size_t num_depths = 0;             // pixels with a photometrically valid depth, all views
  size_t num_beside_background = 0;  // of which dropped beside the open background
  size_t num_consistent = 0;         // of which geometrically consistent
  size_t num_points = 0;             // fused
  double seconds_undistort = 0;
  double seconds_patchmatch = 0;
  double seconds_fusion = 0;
};

// What else the depth maps start from or leave alone.
struct MultiViewStereoInputs {
  // Points (with normals, if any) whose depth starts PatchMatch at the pixels they project to in
  // each view, nearest first; the sparse points a view observes always do.
  const PointCloud* prior = nullptr;
  // Points that already stand for the surface: a pixel where one of them projects at or in front
  // of the depth map's depth is left out of fusion (PatchMatch fills where they stop).
  const PointCloud* covered = nullptr;
};

// `load_image(image_id)` returns the photo of a registered image (BGR 8-bit). The fused points
// go to `sink` as fusion makes them (depth_fusion.h). Throws varsfm::Error when no registered
// view has a source view.
void MultiViewStereoInto(const Reconstruction& reconstruction,
                         const std::function<cv::Mat(image_t)>& load_image,
                         const MultiViewStereoOptions& options, const MultiViewStereoInputs& inputs,
                         const FusedPointSink& sink, MultiViewStereoStats* stats = nullptr);

// The same, the points gathered in a cloud.
PointCloud MultiViewStereo(const Reconstruction& reconstruction,
                           const std::function<cv::Mat(image_t)>& load_image,
                           const MultiViewStereoOptions& options,
                           const MultiViewStereoInputs& inputs = {},
                           DenseVisibility* visibility = nullptr,
                           MultiViewStereoStats* stats = nullptr);

}  // namespace varsfm
