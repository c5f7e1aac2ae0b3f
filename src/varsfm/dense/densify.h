#pragma once
// Dense reconstruction from a sparse model (the paper's last stage before the surface): image
// pairs are chosen from the shared 3D points, undistorted, matched quasi-densely by match
// propagation seeded with the sparse points (Lhuillier & Quan 2002), the matches triangulated
// with the known cameras, fused across pairs, coloured, and given PCA normals. Or multi-view
// stereo by PatchMatch depth maps (multi_view_stereo.h), alone or with propagation.
#include <filesystem>
#include <functional>
#include <string_view>
#include <vector>

#include <opencv2/core.hpp>

#include "varsfm/dense/match_propagation.h"
#include "varsfm/dense/multi_view_stereo.h"
#include "varsfm/dense/normals.h"
#include "varsfm/dense/undistorted_view.h"
#include "varsfm/scene/point_cloud.h"
#include "varsfm/scene/reconstruction.h"
#include "varsfm/util/enum_names.h"

namespace varsfm {

// How the dense cloud is made.
enum class DenseMethod {
  kPropagation,  // match propagation of image pairs (the paper's method)
  kPatchMatch,   // PatchMatch depth maps started from the sparse points, fused
  kSeeded,       // PatchMatch depth maps started from propagation's points, fused
  kFill,         // propagation's points, and PatchMatch's where propagation has none
  kSeededFill,   // kFill with PatchMatch started from propagation's points
};

struct DenseReconstructionOptions {
  // PatchMatch by default: on every shared set it renders the held-out views better than
  // propagation (bench/results/2026-12-02-dense-default.md); propagation stays selectable.
  DenseMethod method = DenseMethod::kPatchMatch;
  MultiViewStereoOptions mvs;  // for every method but kPropagation
  // Pair selection: partners share >= min_shared_points 3D points whose median triangulation
  // angle lies in [min, max] degrees; each image keeps its best `max_partners` (most shared).
  int max_partners = 2;
  int min_shared_points = 15;
  double min_pair_angle_deg = 3.0;
  double max_pair_angle_deg = 40.0;
  // Images are matched at most this size (longer side, px); larger ones are downscaled.
  int max_image_size = 1600;
  PropagationOptions propagation;
  bool use_epipolar_constraint = true;
  // Per-point filters.
  double min_point_angle_deg = 1.0;
  double max_reprojection_error = 1.0;  // px, in the (possibly downscaled) matching images
  // Fusion: a point merges with one already projecting on the same pixel of a shared view when
  // their depths agree within this relative tolerance.
  double fusion_depth_tolerance = 0.01;
  int min_views = 2;  // observations a fused point needs (2: one pair)
  int normal_neighbors = 20;
  int num_threads = 0;  // 0: all cores

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

struct DensifyStats {
  size_t num_pairs = 0;
  size_t num_matches = 0;          // quasi-dense matches over all pairs
  size_t num_triangulated = 0;     // after the angle / reprojection filters
  size_t num_points = 0;           // after fusion
  double seconds_undistort = 0;    // loading and undistorting the images
  double seconds_propagation = 0;  // propagation and triangulation of all pairs
  double seconds_fusion = 0;       // fusion and the reprojection check
  double seconds_normals = 0;
  MultiViewStereoStats mvs;  // zeros for kPropagation
};

// The image pairs densify would match (image ids, first < second, sorted).
std::vector<std::pair<image_t, image_t>> SelectDensePairs(
    const Reconstruction& reconstruction, const DenseReconstructionOptions& options);

// The names `--dense-method` takes and summaries give.
inline constexpr EnumName<DenseMethod> kDenseMethodNames[] = {
    {DenseMethod::kPropagation, "propagation"},
    {DenseMethod::kPatchMatch, "patchmatch"},
    {DenseMethod::kSeeded, "seeded"},
    {DenseMethod::kFill, "fill"},
    {DenseMethod::kSeededFill, "seeded-fill"}};

// `load_image(image_id)` returns the photo of a registered image (BGR 8-bit). `visibility`, when
// given, gets the ids of the images that see each point. Throws varsfm::Error when the model has
// fewer than two registered images or no usable pair.
PointCloud Densify(const Reconstruction& reconstruction,
                   const std::function<cv::Mat(image_t)>& load_image,
                   const DenseReconstructionOptions& options = {}, DensifyStats* stats = nullptr,
                   DenseVisibility* visibility = nullptr);

// Whether a method's points can be handed over one by one as they are made (DensifyInto):
// PatchMatch's alone, whose fusion makes each point once; the other methods gather theirs to
// merge, filter or combine them.
inline bool StreamsPoints(DenseMethod method) { return method == DenseMethod::kPatchMatch; }

// Densify for a method that StreamsPoints: each point goes to `sink` as fusion makes it, so the
// cloud never stands whole in memory (a thousand photos at 800 px make tens of millions of
// points). Throws varsfm::Error as Densify, and for a method that does not stream.
void DensifyInto(const Reconstruction& reconstruction,
                 const std::function<cv::Mat(image_t)>& load_image,
                 const DenseReconstructionOptions& options, DensifyStats* stats,
                 const FusedPointSink& sink);

}  // namespace varsfm
