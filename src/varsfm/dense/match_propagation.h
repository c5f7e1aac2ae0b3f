#pragma once
// Quasi-dense matching of one image pair by match propagation (Lhuillier & Quan, "Match
// propagation for image-based modeling and rendering", PAMI 2002, section 3): sparse seed
// matches are grown best-first into their neighbourhoods under ZNCC, uniqueness, a disparity
// gradient limit, a texture test and, when F is known, the epipolar constraint.
// Speed (fountain-P11: ~330,000 matches per 1024x683 pair in 1-2 s on one core): ZNCC from
// per-pixel window sums and exact integer cross sums (dense/zncc.h); the best-first list is a
// bucket queue (order exact to 5e-5 in ZNCC); a pixel is not re-tried by a second parent with
// the same disparity (same candidates, already queued).
//
// Pixel coordinates follow varsfm's convention: pixel (c, r) covers [c, c+1) x [r, r+1), so a
// match between pixel centres is reported as (c + 0.5, r + 0.5).
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace varsfm {

struct PropagationOptions {
  int window_radius = 3;  // ZNCC window (2 r + 1)^2: 7x7 (the paper: 5x5), steadier sub-pixel peaks
  double min_zncc = 0.8;  // the paper's acceptance threshold z
  // Texture test (the paper's confidence s(x) = max |I(x + D) - I(x)| over the 4 neighbours
  // D, t = 0.01 for intensities in [0, 1]); in gray levels here. Also the window's standard
  // deviation must exceed `min_window_std` so ZNCC is defined and not dominated by noise.
  double min_gradient = 2.5;
  double min_window_std = 1.0;
  double max_epipolar_distance = 1.5;  // px, only when F is given
  bool subpixel = true;                // parabola fit of ZNCC in image 2 (one axis at a time)
  size_t max_matches = 0;              // 0: no cap

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

struct SeedMatch {
  Eigen::Vector2d x1, x2;  // pixels, varsfm convention
};

struct QuasiDenseMatch {
  Eigen::Vector2f x1;  // pixel centre in image 1
  Eigen::Vector2f x2;  // image 2, sub-pixel when options.subpixel
  float zncc = 0;
};

// gray1, gray2: 8-bit single-channel images. F (optional): x2^T F x1 = 0 in pixel coordinates.
// Matches are returned in acceptance order (seeds and growth); every pixel of either image
// appears at most once. Deterministic.
std::vector<QuasiDenseMatch> PropagateMatches(const cv::Mat& gray1, const cv::Mat& gray2,
                                              const std::vector<SeedMatch>& seeds,
                                              const PropagationOptions& options = {},
                                              const std::optional<Eigen::Matrix3d>& F = {});

}  // namespace varsfm
