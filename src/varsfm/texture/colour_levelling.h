#pragma once
// Global colour levelling across seams (Waechter, Moehrle & Goesele, "Let there be color!",
// ECCV 2014, sec. 4.1): every vertex gets one additive colour correction per image that
// textures a face around it, g_(v,l). The corrections minimise
//   sum over seam vertices v, label pairs (l1, l2) at v: (f_(v,l1) + g_(v,l1) - f_(v,l2) -
//   g_(v,l2))^2
//   + smoothness x sum over edges (v_i, v_j) of faces with label l: (g_(v_i,l) - g_(v_j,l))^2
//   + ridge x sum g^2
// where f_(v,l) is image l's colour at v, averaged along the seam edges at v (weights falling
// linearly from v) so that one pixel of detail does not decide it. The first term closes the
// colour gaps at seams, the second spreads each correction smoothly over its chart, and the ridge
// makes it fade over about sqrt(smoothness / ridge) edges from the seam: the exposure gains
// have already removed the photos' global differences, and a correction carried across a whole
// chart from a few noisy seam samples (misregistered detail) rendered held-out views worse than
// no levelling, a local one better (the texture labelling-and-levelling results in
// bench/results). Sparse and symmetric positive definite: one Cholesky
// factorisation (Eigen's SimplicialLDLT), three right-hand sides (B, G, R). Colours are compared
// after the exposure gains, which leaves the levelling the local differences only.
#include <array>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "varsfm/texture/face_observations.h"

namespace varsfm {

struct ColourLevellingOptions {
  bool enabled = true;
  double smoothness = 1.0;
  double ridge = 0.1;
  int max_samples_per_edge = 16;
  // Seam colours farther apart than this (grey levels, BGR Euclidean) are left alone.
  double max_seam_difference = 50;
  // Systems of up to this many unknowns (a corner's vertex and label) are solved by sparse
  // Cholesky, larger ones by conjugate gradients to this relative residual.
  int direct_max_unknowns = 1000000;
  double iterative_tolerance = 1e-6;
  void Check() const;
};

// Per face, the BGR correction (grey levels) at its three corners, in its label's image after
// that image's gain; zero for unlabelled faces and when disabled.
std::vector<std::array<Eigen::Vector3f, 3>> LevelColours(
    const std::vector<Eigen::Vector3d>& vertices, const std::vector<Eigen::Vector3i>& faces,
    const std::vector<int>& labels, const std::vector<PosedCamera>& views,
    const std::vector<cv::Mat>& small_photos, const std::vector<double>& small_scale,
    const std::vector<Eigen::Vector3f>& gains, const ColourLevellingOptions& options = {});

}  // namespace varsfm
