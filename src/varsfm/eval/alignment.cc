#include "varsfm/eval/alignment.h"
#include "varsfm/util/option_check.h"

#include <array>
#include <optional>

#include <Eigen/Geometry>
#include <Eigen/SVD>

namespace varsfm {
namespace {

// Least-squares similarity over the points `idx`; nullopt when the source points are
// collinear (rotation about their line undetermined) or coincide.
std::optional<Sim3d> Fit(const std::vector<Eigen::Vector3d>& source,
                         const std::vector<Eigen::Vector3d>& target,
                         const std::vector<size_t>& idx) {
  Eigen::Matrix3Xd src(3, idx.size()), dst(3, idx.size());
  for (size_t i = 0; i < idx.size(); ++i) {
    src.col(i) = source[idx[i]];
    dst.col(i) = target[idx[i]];
  }
  const Eigen::Matrix3Xd centred = src.colwise() - src.rowwise().mean();
  const Eigen::Vector3d sv = Eigen::JacobiSVD<Eigen::Matrix3Xd>(centred).singularValues();
  if (sv[0] <= 0.0 || sv[1] < 1e-9 * sv[0]) return std::nullopt;
  const Eigen::Matrix4d T = Eigen::umeyama(src, dst, /*with_scaling=*/true);
  Sim3d sim;
  sim.scale = T.block<3, 1>(0, 0).norm();
  if (!(sim.scale > 0.0)) return std::nullopt;
  sim.rotation = T.block<3, 3>(0, 0) / sim.scale;
  sim.translation = T.block<3, 1>(0, 3);
  return sim;
}

std::vector<size_t> InliersOf(const Sim3d& sim, const std::vector<Eigen::Vector3d>& source,
                              const std::vector<Eigen::Vector3d>& target, double threshold) {
  std::vector<size_t> inliers;
  for (size_t i = 0; i < source.size(); ++i)
    if ((sim * source[i] - target[i]).norm() < threshold) inliers.push_back(i);
  return inliers;
}

// The 3-point samples RANSAC tries: every triple when there are few, else random ones.
std::vector<std::array<size_t, 3>> Samples(size_t n, const AlignmentOptions& options) {
  std::vector<std::array<size_t, 3>> samples;
  const double num_triples = static_cast<double>(n) * (n - 1) * (n - 2) / 6.0;
  if (num_triples <= options.max_trials) {
    for (size_t a = 0; a < n; ++a)
      for (size_t b = a + 1; b < n; ++b)
        for (size_t c = b + 1; c < n; ++c) samples.push_back({a, b, c});
    return samples;
  }
  Rng rng(options.seed);
  std::uniform_int_distribution<size_t> pick(0, n - 1);
  while (samples.size() < static_cast<size_t>(options.max_trials)) {
    const size_t a = pick(rng), b = pick(rng), c = pick(rng);
    if (a != b && b != c && a != c) samples.push_back({a, b, c});
  }
  return samples;
}

}  // namespace

Sim3d Sim3d::Inverse() const {
  Sim3d inv;
  inv.scale = 1.0 / scale;
  inv.rotation = rotation.transpose();
  inv.translation = -inv.scale * (inv.rotation * translation);
  return inv;
}

AlignmentResult AlignSimilarity(const std::vector<Eigen::Vector3d>& source,
                                const std::vector<Eigen::Vector3d>& target,
                                const AlignmentOptions& options) {
  AlignmentResult result;
  const size_t n = source.size();
  if (n < 3 || target.size() != n) return result;
  std::vector<size_t> all(n);
  for (size_t i = 0; i < n; ++i) all[i] = i;

  std::vector<size_t> chosen = all;
  if (options.inlier_threshold > 0.0) {
    std::vector<size_t> best;
    for (const auto& s : Samples(n, options)) {
      const auto sim = Fit(source, target, {s[0], s[1], s[2]});
      if (!sim) continue;
      auto inliers = InliersOf(*sim, source, target, options.inlier_threshold);
      if (inliers.size() > best.size()) best = std::move(inliers);
    }
    if (best.size() < 3) return result;
    // Refit on the consensus set, then take the inliers of that final fit.
    const auto refit = Fit(source, target, best);
    if (!refit) return result;
    chosen = InliersOf(*refit, source, target, options.inlier_threshold);
    if (chosen.size() < 3) chosen = best;
  }
  const auto sim = Fit(source, target, chosen);
  if (!sim) return result;
  result.success = true;
  result.sim = *sim;
  result.inliers.assign(n, false);
  for (size_t i : chosen) result.inliers[i] = true;
  result.num_inliers = chosen.size();
  return result;
}

void AlignmentOptions::Check() const {
  CheckNonNegative("--inlier-threshold", inlier_threshold);
  CheckAtLeast("max_trials", max_trials, 1);
}

}  // namespace varsfm
