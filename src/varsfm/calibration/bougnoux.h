#pragma once
// Closed-form focal lengths from a fundamental matrix (Bougnoux, "From projective to Euclidean
// space under any practical situation", ICCV 1998), used by varsfm's two-view self-calibration
// instead of the paper's linear system (docs/self_calibration.md explains why).
#include <optional>
#include <utility>

#include <Eigen/Core>

namespace varsfm {

// Focal lengths (f1, f2) in pixels of two cameras with unit aspect, zero skew and known
// principal points pp1, pp2, from F (x2^T F x1 = 0). nullopt when either f^2 <= 0 (noise or a
// degenerate configuration) or the formula is singular.
std::optional<std::pair<double, double>> BougnouxFocalLengths(const Eigen::Matrix3d& F,
                                                              const Eigen::Vector2d& pp1,
                                                              const Eigen::Vector2d& pp2);

// One focal length shared by both images (Mendonca-Cipolla): the f in [min_focal, max_focal]
// that makes the two non-zero singular values of E = K^T F K equal, minimising
// (s1 - s2) / s1 by a log-spaced scan refined by golden-section search. nullopt when the best
// cost stays above `max_cost` (no f makes E essential).
std::optional<double> EqualFocalLength(const Eigen::Matrix3d& F, const Eigen::Vector2d& pp1,
                                       const Eigen::Vector2d& pp2, double min_focal,
                                       double max_focal, double max_cost = 0.05);

}  // namespace varsfm
