#pragma once
// From per-view depth maps to one point cloud: a geometric-consistency filter (a depth is kept
// when enough other views' depth maps, followed forward to their pixel and back, land on the
// same pixel at the same depth: Schoenberger et al. 2016, section 4.2's forward-backward
// reprojection), then fusion (as COLMAP's StereoFusion does): each pixel not yet fused starts a
// point, the pixels of the other views where that point projects join it when their depth and
// normal agree, and the point is kept when enough views joined. Each fused point carries the
// images that see it (its visibility), which a visibility-based surface needs.
#include <algorithm>
#include <functional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "varsfm/dense/patchmatch.h"
#include "varsfm/scene/point_cloud.h"
#include "varsfm/util/types.h"

namespace varsfm {

// Per fused point, the ids of the images that see it (ascending); io/point_visibility.h writes
// it beside the cloud.
using DenseVisibility = std::vector<std::vector<image_t>>;

struct DepthFusionOptions {
  double max_reprojection_error = 1.0;  // px, forward-backward
  double max_depth_difference = 0.01;   // relative
  // Fusion only. Wider than COLMAP's 10 deg: a pixel's normal is fitted to a window a few
  // pixels wide and varies by about 10 deg on a plane (tests/dense/patchmatch_test.cc).
  double max_normal_angle_deg = 30.0;
  int min_consistent_views = 2;  // other views agreeing with a depth for it to stay
  int min_fused_views = 3;       // views (the starting one included) a point needs
  // The views each depth is checked against and fused with: the ones that share the most sparse
  // points with its own (FusionView::overlapping), COLMAP's check_num_images.
  int max_overlapping_views = 50;
  // A surface near the cameras or at the edge of the capture is seen by only two views, which
  // the counts above leave out however right its depths. A depth whose photometric cost is at
  // most this (1 - NCC) needs one confirming view and fuses with two (0: no such exception).
  // Held-out figures: bench/results/2026-12-03-two-view-default.md.
  double two_view_max_cost = 0.1;

  // The fewest other views any depth needs to confirm it: min_consistent_views, or at most one
  // when two-view depths are on. One rule for the filter and for explaining an empty cloud.
  int FewestConfirmingViews() const {
    return two_view_max_cost > 0 ? std::min(min_consistent_views, 1) : min_consistent_views;
  }

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

// A view's depth map with what fusion needs to place and colour it.
struct FusionView {
  image_t image_id = kInvalidImageId;
  Eigen::Matrix3d K;  // of the depth map's pixels
  Rigid3d cam_from_world;
  cv::Mat color;  // BGR 8-bit, the depth map's size
  DepthMap map;
  // The views (indices into the fusion's views, ascending) its depths are checked against and
  // fused with: those that may see what it sees (OverlappingViews, source_views.h). Empty:
  // every other view.
  std::vector<uint32_t> overlapping;
};

// Drops (depth 0) every depth that fewer than min_consistent_views other views confirm. Parallel
// over views; every view's result is computed before any map changes, so it is deterministic.
void FilterByGeometricConsistency(std::vector<FusionView>* views,
                                  const DepthFusionOptions& options);

// One fused point: the members' mean position, mean normal (unit, world frame) and mean colour
// (RGB), and the ids of the images that see it (ascending).
struct FusedPoint {
  Eigen::Vector3d position;
  Eigen::Vector3d normal;
  Eigen::Matrix<uint8_t, 3, 1> color;
  std::vector<image_t> seen_by;
};

// Takes each fused point as fusion makes it, in fusion's order and on the calling thread: a stage
// that writes the points out as they come never holds the whole cloud (io/point_cloud_stream.h).
using FusedPointSink = std::function<void(FusedPoint&&)>;

// Fuses the depth maps in view order and row-major pixel order (deterministic), handing each
// point to `sink` in that order.
void FuseDepthMaps(const std::vector<FusionView>& views, const DepthFusionOptions& options,
                   const FusedPointSink& sink);

// The same points gathered in a cloud; `visibility`, when given, gets one entry per point.
PointCloud FuseDepthMaps(const std::vector<FusionView>& views, const DepthFusionOptions& options,
                         DenseVisibility* visibility = nullptr);

// A sink that appends to `cloud` (points, normals, colours) and, when given, to `visibility`.
FusedPointSink AppendTo(PointCloud* cloud, DenseVisibility* visibility);

}  // namespace varsfm
