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
//   // Optional (RansacOptions::degeneracy_recovery): models to try when `model`, a new best,
//   // came from a degenerate minimal `sample`.
//   void DegeneracyModels(const std::vector<int>& sample, const Model& model,
//                         const RansacOptions& options, Rng* rng, std::vector<Model>*) const;
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "varsfm/estimators/neighbourhood_graph.h"
#include "varsfm/util/graph_cut.h"
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
  // Graph-cut local optimisation (Barath & Matas, "Graph-Cut RANSAC", CVPR 2018), in place of the
  // iterated least squares when Ransac() is given a neighbourhood: the data are labelled inlier
  // or outlier by an s-t minimum cut of a truncated-quadratic data term (truncated at 1.5 x
  // max_error) and a term that prefers neighbours to share a label, weighted by
  // spatial_coherence (lambda; the data term by 1 - lambda); then an inner RANSAC fits
  // lo_iterations random subsets of lo_sample_factor x the minimal sample of the labelled
  // inliers; repeated while the best model improves, at most max_graph_cuts times. The paper
  // weights the pairs 0.975; on the Strecha sets' verification 0.2 keeps fewer wrong matches
  // (bench/results/2026-12-04-gc-ransac.md).
  double spatial_coherence = 0.2;
  int lo_sample_factor = 7;
  int lo_iterations = 20;
  int max_graph_cuts = 10;
  // Estimators that offer it test each new best model of a minimal sample for a degenerate
  // sample; a model of a degenerate sample is replaced by the models that recover from it: the
  // fundamental matrix's DEGENSAC (fundamental_degeneracy.h; two_view_estimators.h). Off by
  // default, where an F is estimated the models stay as they were.
  bool degeneracy_recovery = false;
  // The recovery's own sampling (DEGENSAC: pairs of correspondences off the plane) runs an
  // adaptive number of trials for `confidence`, between these bounds.
  int degeneracy_min_trials = 100;
  int degeneracy_max_trials = 1000;
  // After the sampling, the best model is tested on up to this many minimal samples of its own
  // inliers (it may have become degenerate in its local optimisation); the first that finds it
  // degenerate runs the recovery.
  int degeneracy_final_samples = 10;
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

// The graph-cut labelling of Barath & Matas 2018 (sec. 3) for `model`: source side = inlier.
// Per datum, with e = r^2 / (2.25 t^2): an inlier label costs (1 - lambda) e above e = 1, an
// outlier label (1 - lambda)(1 - e) below it; per neighbouring pair, lambda when the labels
// differ and lambda (min(e_p, 1) + min(e_q, 1)) / 2 when both are outliers. The pair term is
// written as two terminal weights and one arc (Kolmogorov & Zabih, PAMI 2004).
template <typename Estimator>
void GraphCutInliers(const Estimator& estimator, const typename Estimator::Model& model,
                     double threshold2, const NeighbourhoodGraph& neighbourhood, double lambda,
                     std::vector<int>* inliers) {
  const size_t n = estimator.NumData();
  const double truncated2 = 2.25 * threshold2;
  std::vector<double> e(n);
  MinCut cut(n, neighbourhood.edges.size());
  for (size_t i = 0; i < n; ++i) {
    e[i] = estimator.SquaredResidual(model, i) / truncated2;
    if (!(e[i] <= 1.0)) {
      cut.SetTerminalWeights(i, 0.0, (1 - lambda) * (std::isfinite(e[i]) ? e[i] : 1e6));
      e[i] = 1.0;
    } else {
      cut.SetTerminalWeights(i, (1 - lambda) * (1 - e[i]), 0.0);
    }
  }
  for (const auto& [p, q] : neighbourhood.edges) {
    // E(in, in) = 0, E(in, out) = E(out, in) = lambda, E(out, out) = lambda m:
    // lambda [p out] + lambda (1 - m) [q in] + lambda (2 - m) [p in, q out] - lambda (1 - m).
    const double m = 0.5 * (e[p] + e[q]);
    cut.SetTerminalWeights(p, lambda, 0.0);
    cut.SetTerminalWeights(q, 0.0, lambda * (1 - m));
    cut.AddEdge(p, q, lambda * (2 - m), 0.0);
  }
  const std::vector<bool> source_side = cut.Solve();
  inliers->clear();
  for (size_t i = 0; i < n; ++i)
    if (source_side[i]) inliers->push_back(static_cast<int>(i));
}

// Fills `sample` with distinct indices from `pick`, by rejection (the sample is much smaller
// than the data).
inline void DrawSample(std::uniform_int_distribution<size_t>& pick, Rng* rng,
                       std::vector<int>* sample) {
  for (size_t k = 0; k < sample->size(); ++k) {
    int index;
    do {
      index = static_cast<int>(pick(*rng));
    } while (std::find(sample->begin(), sample->begin() + static_cast<long>(k), index) !=
             sample->begin() + static_cast<long>(k));
    (*sample)[k] = index;
  }
}

// Moves `count` distinct members, drawn uniformly, to the front of `items` (a partial
// Fisher-Yates shuffle); count <= items->size().
inline void ShuffleFront(size_t count, std::vector<int>* items, Rng* rng) {
  for (size_t k = 0; k < count; ++k) {
    std::uniform_int_distribution<size_t> rest(k, items->size() - 1);
    std::swap((*items)[k], (*items)[rest(*rng)]);
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

// One Ransac() run's state: the best model so far, and the steps that improve it.
template <typename Estimator>
class Search {
 public:
  using Model = typename Estimator::Model;
  static constexpr int kSample = Estimator::kMinSampleSize;
  static constexpr bool kRecovers =
      requires(const Estimator& e, const std::vector<int>& s, const Model& m,
               const RansacOptions& o, Rng* r, std::vector<Model>* out) {
    e.DegeneracyModels(s, m, o, r, out);
  };

  Search(const Estimator& estimator, const RansacOptions& options,
         const NeighbourhoodGraph* neighbourhood)
      : estimator_(estimator),
        options_(options),
        neighbourhood_(neighbourhood),
        threshold2_(options.max_error * options.max_error),
        rng_(options.seed),
        pick_(0, estimator.NumData() - 1),
        sample_(kSample) {}

  const Score& best() const { return best_; }

  // Draws a minimal sample and keeps the best of its models that beats the best so far; true
  // when one did.
  bool TrySample() {
    DrawSample(pick_, &rng_, &sample_);
    candidates_.clear();
    estimator_.MinimalSolve(sample_, &candidates_);
    bool improved = false;
    for (const Model& model : candidates_) {
      const Score score = ScoreOf(model);
      if (!(score.cost < best_.cost)) continue;
      // A new best from a degenerate sample (DEGENSAC: five of F's seven points on one plane)
      // is not taken itself: it fits the plane and whatever off-plane data the rest of its
      // sample picked, on a facade often wrong matches. Only the models recovered from the
      // plane and the parallax of the other data compete (Chum, Werner & Matas, "Two-view
      // geometry estimation unaffected by a dominant plane", CVPR 2005; OpenCV's USAC does the
      // same).
      if (kRecovers && options_.degeneracy_recovery) {
        improved |= Recover(model);
        if (!models_.empty()) continue;
      }
      Keep(score, model);
      improved = true;
    }
    return improved;
  }

  // The local optimisation of a new best model, as the options and the neighbourhood choose.
  void Optimize() {
    if (options_.local_optimization) neighbourhood_ ? GraphCutOptimize() : LocalOptimize();
  }

  // The best model may have become degenerate in its local optimisation rather than from a
  // degenerate sample (least squares on inliers mostly from one plane): it is tested once more
  // on minimal samples of its own inliers.
  void TestForDegeneracy() {
    if (!(kRecovers && options_.degeneracy_recovery)) return;
    Inliers(estimator_, best_model_, threshold2_, &inliers_);
    for (int trial = 0; trial < options_.degeneracy_final_samples &&
                        inliers_.size() > static_cast<size_t>(kSample);
         ++trial) {
      ShuffleFront(kSample, &inliers_, &rng_);
      sample_.assign(inliers_.begin(), inliers_.begin() + kSample);
      const bool improved = Recover(best_model_);
      if (models_.empty()) continue;  // the model passed the test on this sample
      if (improved) Optimize();
      break;
    }
  }

  // A final refit on all inliers of the best model, kept only if it scores better; the report.
  RansacReport<Model> Finish(int iterations) {
    Inliers(estimator_, best_model_, threshold2_, &inliers_);
    if (inliers_.size() > static_cast<size_t>(kSample)) {
      models_.clear();
      estimator_.NonMinimalSolve(inliers_, best_model_, &models_);
      if (!models_.empty()) Consider(models_.front());
    }
    RansacReport<Model> report;
    report.success = true;
    report.model = best_model_;
    report.iterations = iterations;
    Inliers(estimator_, best_model_, threshold2_, &inliers_);
    report.inlier_mask.assign(estimator_.NumData(), 0);
    for (const int i : inliers_) report.inlier_mask[i] = 1;
    report.num_inliers = inliers_.size();
    return report;
  }

 private:
  // The model's score, or an infinite cost once it is sure to be worse than the best so far.
  Score ScoreOf(const Model& model) const {
    return Evaluate(estimator_, model, threshold2_, options_.msac_score, best_.cost);
  }

  void Keep(const Score& score, const Model& model) {
    best_ = score;
    best_model_ = model;
  }

  // Keeps `model` when it scores better than the best so far.
  bool Consider(const Model& model) {
    const Score score = ScoreOf(model);
    if (!(score.cost < best_.cost)) return false;
    Keep(score, model);
    return true;
  }

  // Least squares on the best model's inliers, then a few rounds of least squares on the
  // inliers at a threshold shrinking from 3t to t (Lebeda et al. 2012, "iterative least
  // squares"), keeping any model that scores better.
  void LocalOptimize() {
    constexpr int kSteps = 4;
    constexpr double kMultiplier = 3.0;
    for (int step = 0; step <= kSteps; ++step) {
      const double m =
          step == 0 ? 1.0 : kMultiplier - (kMultiplier - 1.0) * (step - 1) / (kSteps - 1);
      Inliers(estimator_, best_model_, threshold2_ * m * m, &inliers_);
      if (inliers_.size() <= static_cast<size_t>(kSample)) return;
      models_.clear();
      estimator_.NonMinimalSolve(inliers_, best_model_, &models_);
      if (models_.empty()) return;
      Consider(models_.front());
    }
  }

  // Graph-cut local optimisation (RansacOptions::spatial_coherence).
  void GraphCutOptimize() {
    const size_t subset_size = static_cast<size_t>(options_.lo_sample_factor) * kSample;
    for (int cut = 0; cut < options_.max_graph_cuts; ++cut) {
      GraphCutInliers(estimator_, best_model_, threshold2_, *neighbourhood_,
                      options_.spatial_coherence, &inliers_);
      if (inliers_.size() <= static_cast<size_t>(kSample)) return;
      bool improved = false;
      const bool all = inliers_.size() <= subset_size;
      for (int trial = 0; trial < (all ? 1 : options_.lo_iterations); ++trial) {
        if (all) {
          subset_ = inliers_;
        } else {
          ShuffleFront(subset_size, &inliers_, &rng_);
          subset_.assign(inliers_.begin(), inliers_.begin() + static_cast<long>(subset_size));
        }
        models_.clear();
        estimator_.NonMinimalSolve(subset_, best_model_, &models_);
        for (const Model& model : models_) improved |= Consider(model);
      }
      if (!improved) return;
    }
  }

  // Recovery of `model`, a model of the minimal sample sample_, should the sample be degenerate:
  // the estimator's recovered models are left in models_ (none when it found the sample sound);
  // true when one of them scored better (and became the best). `model` is read before any is
  // scored, so it may be best_model_ itself.
  bool Recover(const Model& model) {
    models_.clear();
    if constexpr (kRecovers) estimator_.DegeneracyModels(sample_, model, options_, &rng_, &models_);
    bool improved = false;
    for (const Model& model : models_) improved |= Consider(model);
    return improved;
  }

  const Estimator& estimator_;
  const RansacOptions& options_;
  const NeighbourhoodGraph* neighbourhood_;
  double threshold2_;
  Rng rng_;
  std::uniform_int_distribution<size_t> pick_;
  Model best_model_{};
  Score best_;
  std::vector<int> sample_, inliers_, subset_;
  std::vector<Model> models_, candidates_;
};

}  // namespace ransac_internal

template <typename Estimator>
RansacReport<typename Estimator::Model> Ransac(const Estimator& estimator,
                                               const RansacOptions& options,
                                               const NeighbourhoodGraph* neighbourhood = nullptr) {
  constexpr int kSample = Estimator::kMinSampleSize;
  RansacReport<typename Estimator::Model> report;
  const size_t n = estimator.NumData();
  if (n < static_cast<size_t>(kSample) || options.max_error <= 0) return report;
  ransac_internal::Search<Estimator> search(estimator, options, neighbourhood);
  int required = options.max_iterations;
  int iteration = 0;
  for (; iteration < std::min(required, options.max_iterations); ++iteration) {
    if (!search.TrySample()) continue;
    search.Optimize();
    required = ransac_internal::RequiredIterations(search.best().num_inliers, n, kSample,
                                                   options.confidence, options.min_iterations,
                                                   options.max_iterations);
  }
  if (search.best().num_inliers < static_cast<size_t>(kSample)) {
    report.iterations = iteration;
    return report;
  }
  search.TestForDegeneracy();
  report = search.Finish(iteration);
  return report;
}

}  // namespace varsfm
