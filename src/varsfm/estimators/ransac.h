#pragma once
// A generic LO-RANSAC (Fischler & Bolles 1981; local optimisation after Chum, Matas & Kittler,
// "Locally optimized RANSAC", DAGM 2003, with the iterated least squares of Lebeda, Matas &
// Chum, "Fixing the locally optimized RANSAC", BMVC 2012).
//
// An Estimator provides:
//   using Model = ...;
//   static constexpr int kMinSampleSize;
//   size_t NumData() const;
//   // Candidate models from kMinSampleSize data indices (several for 7-pt F / 5-pt E).
//   void MinimalSolve(const std::vector<int>& sample, std::vector<Model>* models) const;
//   // Least-squares models from more data (at most one model is used); `initial` is the best
//   // model so far, the starting point of an iterative solver (linear solvers ignore it).
//   void NonMinimalSolve(const std::vector<int>& indices, const Model& initial,
//                        std::vector<Model>* models) const;
//   // Squared residual of datum i (in the units of max_error, squared).
//   double SquaredResidual(const Model& model, size_t i) const;
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "varsfm/util/random.h"

namespace varsfm {

struct RansacOptions {
  double max_error = 4.0;  // inlier threshold on the residual (pixels for pixel data)
  double confidence = 0.9999;
  int min_iterations = 100;
  int max_iterations = 10000;
  bool local_optimization = true;
  // MSAC truncated quadratic loss (Torr & Zisserman 2000) instead of the inlier count; see
  // bench/estimators_bench.cc for the comparison that made it the default.
  bool msac_score = true;
  uint64_t seed = kDefaultSeed;
};

template <typename Model>
struct RansacReport {
  bool success = false;
  Model model{};
  std::vector<char> inlier_mask;
  size_t num_inliers = 0;
  int iterations = 0;
};

namespace ransac_internal {

// Score of a model: lower is better. MSAC: sum of min(r^2, t^2); inlier count: -count with the
// sum of inlier squared residuals (scaled below one threshold unit) breaking ties.
struct Score {
  double cost = std::numeric_limits<double>::infinity();
  size_t num_inliers = 0;
};

template <typename Estimator>
Score Evaluate(const Estimator& estimator, const typename Estimator::Model& model,
               double threshold2, bool msac,
               double bound = std::numeric_limits<double>::infinity()) {
  Score score;
  const size_t n = estimator.NumData();
  double cost = 0, inlier_sum = 0;
  for (size_t i = 0; i < n; ++i) {
    const double r2 = estimator.SquaredResidual(model, i);
    if (r2 < threshold2) {
      ++score.num_inliers;
      cost += r2;
      inlier_sum += r2;
    } else {
      cost += threshold2;
    }
    // The MSAC cost only grows, so a model already worse than the best one can stop here
    // (the result is unchanged; most hypotheses are rejected after a fraction of the data).
    if (msac && cost > bound) return Score{};
  }
  score.cost = msac ? cost
                    : -static_cast<double>(score.num_inliers) +
                          inlier_sum / (threshold2 * static_cast<double>(n + 1));
  return score;
}

template <typename Estimator>
void Inliers(const Estimator& estimator, const typename Estimator::Model& model, double threshold2,
             std::vector<int>* inliers) {
  inliers->clear();
  for (size_t i = 0; i < estimator.NumData(); ++i) {
    if (estimator.SquaredResidual(model, i) < threshold2) inliers->push_back(static_cast<int>(i));
  }
}

// Number of iterations for `confidence` of drawing one all-inlier sample (Fischler & Bolles):
// N = log(1 - p) / log(1 - w^s).
inline int RequiredIterations(size_t num_inliers, size_t num_data, int sample_size,
                              double confidence, int min_iterations, int max_iterations) {
  if (num_data == 0) return max_iterations;
  const double w = static_cast<double>(num_inliers) / static_cast<double>(num_data);
  const double p_good = std::pow(w, sample_size);
  if (p_good <= 0) return max_iterations;
  if (p_good >= 1) return min_iterations;
  const double n = std::log(1 - confidence) / std::log(1 - p_good);
  if (!std::isfinite(n) || n > max_iterations) return max_iterations;
  return std::max(min_iterations, static_cast<int>(std::ceil(n)));
}

}  // namespace ransac_internal

template <typename Estimator>
RansacReport<typename Estimator::Model> Ransac(const Estimator& estimator,
                                               const RansacOptions& options) {
  using Model = typename Estimator::Model;
  using ransac_internal::Score;
  constexpr int kSample = Estimator::kMinSampleSize;
  RansacReport<Model> report;
  const size_t n = estimator.NumData();
  if (n < static_cast<size_t>(kSample) || options.max_error <= 0) return report;

  const double threshold2 = options.max_error * options.max_error;
  const bool msac = options.msac_score;
  Rng rng(options.seed);
  std::uniform_int_distribution<size_t> pick(0, n - 1);

  Model best_model{};
  Score best;
  std::vector<int> sample(kSample), inliers;
  std::vector<Model> models;

  const auto consider = [&](const Model& model) {
    const Score score = ransac_internal::Evaluate(estimator, model, threshold2, msac, best.cost);
    if (score.cost < best.cost) {
      best = score;
      best_model = model;
      return true;
    }
    return false;
  };

  // Local optimisation of a new best model: least squares on its inliers, then a few rounds
  // of least squares on the inliers at a threshold shrinking from 3t to t (Lebeda et al.
  // 2012, "iterative least squares"), keeping any model that scores better.
  const auto local_optimize = [&]() {
    constexpr int kSteps = 4;
    constexpr double kMultiplier = 3.0;
    for (int step = 0; step <= kSteps; ++step) {
      const double m =
          step == 0 ? 1.0 : kMultiplier - (kMultiplier - 1.0) * (step - 1) / (kSteps - 1);
      ransac_internal::Inliers(estimator, best_model, threshold2 * m * m, &inliers);
      if (inliers.size() <= static_cast<size_t>(kSample)) return;
      models.clear();
      estimator.NonMinimalSolve(inliers, best_model, &models);
      if (models.empty()) return;
      consider(models.front());
    }
  };

  int required = options.max_iterations;
  int iteration = 0;
  for (; iteration < std::min(required, options.max_iterations); ++iteration) {
    // A sample of distinct indices by rejection (kSample << n).
    for (int k = 0; k < kSample; ++k) {
      size_t index;
      do {
        index = pick(rng);
      } while (std::find(sample.begin(), sample.begin() + k, static_cast<int>(index)) !=
               sample.begin() + k);
      sample[k] = static_cast<int>(index);
    }
    models.clear();
    estimator.MinimalSolve(sample, &models);
    bool improved = false;
    for (const Model& model : models) improved |= consider(model);
    if (!improved) continue;
    if (options.local_optimization) local_optimize();
    required = ransac_internal::RequiredIterations(best.num_inliers, n, kSample, options.confidence,
                                                   options.min_iterations, options.max_iterations);
  }

  if (best.num_inliers < static_cast<size_t>(kSample)) {
    report.iterations = iteration;
    return report;
  }
  // Final refit on all inliers of the best model, kept only if it scores at least as well.
  ransac_internal::Inliers(estimator, best_model, threshold2, &inliers);
  if (inliers.size() > static_cast<size_t>(kSample)) {
    models.clear();
    estimator.NonMinimalSolve(inliers, best_model, &models);
    if (!models.empty()) consider(models.front());
  }

  report.success = true;
  report.model = best_model;
  report.iterations = iteration;
  report.inlier_mask.assign(n, 0);
  report.num_inliers = 0;
  for (size_t i = 0; i < n; ++i) {
    if (estimator.SquaredResidual(best_model, i) < threshold2) {
      report.inlier_mask[i] = 1;
      ++report.num_inliers;
    }
  }
  return report;
}

}  // namespace varsfm
