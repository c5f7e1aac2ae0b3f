#pragma once
// PatchMatch multi-view stereo for one reference view: every pixel carries a plane hypothesis
// (depth along the optical axis and a normal, in the reference camera's frame) whose cost is the
// bilateral-weighted NCC of the reference window against its homography warp into the source
// views (Bleyer et al., "PatchMatch Stereo", BMVC 2011; multi-view form of Schoenberger et al.,
// "Pixelwise View Selection for Unstructured Multi-View Stereo", ECCV 2016). The views' costs are
// aggregated as the mean of the best few (the views that see the point unoccluded agree; the
// others do not), as Xu & Tao's ACMH does. Hypotheses spread by checkerboard propagation
// (Galliani et al., "Massively Parallel Multiview Stereopsis by Surface Normal Diffusion", ICCV
// 2015): the red pixels are updated from black neighbours, then the black from red, so every
// update of a half-sweep reads only pixels that half-sweep does not write. With a random number
// generator per pixel and sweep the result is the same bits at any thread count.
#include <cstdint>
#include <filesystem>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "varsfm/geometry/rigid3.h"
#include "varsfm/util/scratch_array.h"

namespace varsfm {

struct PatchMatchOptions {
  int window_radius = 5;  // NCC window (2 r + 1)^2, sampled every `window_step` pixels
  int window_step = 2;
  // Bilateral weights exp(-dI^2 / 2 sigma_color^2 - dx^2 / 2 sigma_spatial^2) (Yoon & Kweon
  // 2006), intensities in [0, 1]: pixels of the window unlike the centre count less, so windows
  // across depth edges are matched by their centre's side. 0.1 rather than COLMAP's 0.2: with
  // 0.2 a roof's dark pixels, weighted 0.04 each, still outweigh the sky's noise in the centre
  // pixel's window, so sky beside a roofline matched at the roof's depth (a halo); 0.1 weights
  // them 4e-6 (bench/results/2026-12-04-sigma-color.md).
  double sigma_color = 0.1;
  double sigma_spatial = 3.0;
  int num_iterations = 4;  // red + black sweeps (at the coarsest level, with num_levels > 1)
  // Coarse to fine: 2 or more estimates the map first at half the size (recursively) and starts
  // from its planes; 1: the given size only. At half the size the same window spans four times
  // the area, so planes converge on weak texture, and a sweep costs a quarter: with two sweeps
  // at the full size instead of four, the shared sets' held-out views are covered as well or
  // better at the same PSNR for about a third less PatchMatch time
  // (bench/results/2026-12-07-s41-coarse-to-fine.md).
  int num_levels = 2;
  // Sweeps at each level that starts from a coarser level's planes (0: num_iterations): those
  // planes start it nearly converged, so it needs fewer.
  int num_fine_iterations = 2;
  // A second pass at the finest level whose cost adds, per source view, geometric_weight x the
  // forward-backward reprojection error (px, capped at geometric_max_error) through the source's
  // first-pass depth map (Schoenberger et al. 2016, eq. 11; COLMAP's 0.3 and 3 px). 0: none.
  int num_geometric_iterations = 0;
  double geometric_weight = 0.3;
  double geometric_max_error = 3.0;
  // The planar prior's term (planar_prior.h; Xu & Tao 2020): a hypothesis pays planar_weight x
  // (1 - exp(-(e_d^2 + e_n^2) / 2)), e_d its depth's difference from the prior plane's over
  // planar_depth_sigma x that depth, e_n its normal's angle to the plane's over
  // planar_normal_sigma_deg, so the prior decides where the photometric cost is nearly flat and
  // gives way where it has a clear minimum elsewhere.
  double planar_weight = 0.2;
  double planar_depth_sigma = 0.02;
  double planar_normal_sigma_deg = 15.0;
  // Whether flat windows (min_ncc_variance) take their prior plane: a blank wall between textured
  // edges, but also the sky between a roof's spires, which other views' priors span alike.
  bool planar_fill_flat = true;
  // The cost is the mean of this many lowest per-view costs. One: a source to which the pixel's
  // surface is hidden behind something else matches badly at the true depth, and in a mean of
  // two it let wrong planes that half-match both sources win over the true one that the other
  // source sees (on the rendered scene's floor behind its boxes, half the pixels three or four
  // views see went without a point); a depth from one source is still judged by its consistency
  // with other views' depth maps. Held-out figures: bench/results/2026-12-04-best-view.md.
  int num_best_views = 1;
  // A source the pixel's point falls outside of (or behind) is left out of that mean, which then
  // pays this for each view it lacks; < 0: such a source counts as the worst match. 0 lets a
  // pixel one source sees take its depth from that one, as two-view stereo does: counted as a
  // failed match, the missing view left the true plane no better than wrong ones that bring
  // another source in, so the edges of every view went without depth (bench/results,
  // 2026-12-04-missing-view.md). Consistency across views still judges each depth. With
  // num_best_views 1 a pixel never lacks a view it asks for, so this then changes nothing.
  double missing_view_penalty = 0;
  double max_cost = 0.6;           // 1 - NCC above which a pixel's depth is dropped at the end
  double min_ncc_variance = 1e-5;  // reference windows flatter than this get no depth

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

// An undistorted view: intensities in [0, 1] (CV_32F), its pinhole K and pose.
struct PatchMatchView {
  cv::Mat gray;
  Eigen::Matrix3d K;
  Rigid3d cam_from_world;
};

// Per-pixel depth (along the optical axis; 0: none) and unit normal in the camera frame, and the
// photometric cost of the final hypothesis. Row-major, width x height.
// Filled on the heap; MoveToScratch moves the three arrays into one scratch memory.
struct DepthMap {
  int width = 0, height = 0;
  ScratchArray<float> depth;
  ScratchArray<Eigen::Vector3f> normal;
  ScratchArray<float> cost;

  size_t Index(int x, int y) const { return static_cast<size_t>(y) * width + x; }
  // Moves the arrays into scratch memory in `folder` (util/scratch_memory.h).
  void MoveToScratch(const std::filesystem::path& folder);
};

// The depth range searched and, optionally, prior depths and normals (depth 0 where none) that
// replace the random initial hypothesis where given (sparse points, match propagation).
struct PatchMatchInit {
  float min_depth = 0, max_depth = 0;
  DepthMap prior;  // empty, or the reference view's size
  // Prior planes (planar_prior.h) that a second pass (RefineDepthMap) weighs into the cost:
  // empty, or the reference view's size, depth 0 where none. A pixel whose final depth agrees
  // with its prior plane (within 2 planar_depth_sigma) keeps it whatever its photometric cost,
  // a flat one included: in weak texture the photometric cost cannot confirm a depth, and
  // geometric consistency across views is left to judge it (depth_fusion.h).
  DepthMap planar;
};

// The depth map of views[reference] against views[s] for s in `sources`. `seed` fixes every
// random draw (with the pixel and sweep). Parallel over rows (TBB).
// `drop_uncertain`: false keeps the depths above max_cost (with their cost), for a geometric pass.
DepthMap EstimateDepthMap(const std::vector<PatchMatchView>& views, uint32_t reference,
                          const std::vector<uint32_t>& sources, const PatchMatchInit& init,
                          const PatchMatchOptions& options, uint64_t seed,
                          bool drop_uncertain = true);

// A second pass of `num_iterations` sweeps over views[reference], started from `start` (a first
// pass's map, uncertain depths included): with the geometric term when `source_maps` is not empty
// (as RefineDepthMapGeometrically) and the planar prior when init.planar is not empty.
// `drop_uncertain` as for EstimateDepthMap.
DepthMap RefineDepthMap(const std::vector<PatchMatchView>& views, uint32_t reference,
                        const std::vector<uint32_t>& sources,
                        const std::vector<const DepthMap*>& source_maps, const DepthMap& start,
                        const PatchMatchInit& init, const PatchMatchOptions& options, uint64_t seed,
                        int num_iterations, bool drop_uncertain = true);

// The geometric pass (options.num_geometric_iterations sweeps) of views[reference], started from
// its first-pass map `start`; `source_maps[k]` is the first-pass map of views[sources[k]] (null:
// none, every point then counts as inconsistent in that view). Depths above max_cost (photometric
// alone) are dropped.
DepthMap RefineDepthMapGeometrically(const std::vector<PatchMatchView>& views, uint32_t reference,
                                     const std::vector<uint32_t>& sources,
                                     const std::vector<const DepthMap*>& source_maps,
                                     const DepthMap& start, const PatchMatchInit& init,
                                     const PatchMatchOptions& options, uint64_t seed);

}  // namespace varsfm
