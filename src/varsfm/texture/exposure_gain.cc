#include "varsfm/texture/exposure_gain.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>
#include <Eigen/Dense>

#include "varsfm/util/option_check.h"
#include "varsfm/util/progress.h"

namespace varsfm {

namespace {

// A pair of views (i < j) that shares enough usable faces: their number and, per channel, the
// median of log(colour_i / colour_j) over them, negated (m_ij = log(gain_i / gain_j)).
struct PairEstimate {
  size_t i = 0, j = 0;
  double n = 0;
  double m[3] = {0, 0, 0};
};

// The pairs in (i, j) order. View i's pairs with later views are estimated from i's log-ratios
// alone, so the views are taken in parallel, each holding only its own (all pairs' at once grew
// with the square of the views seeing a face; docs/measurements.md), and their pairs are put
// together in view order: the same pairs at any thread count.
std::vector<PairEstimate> PairEstimates(const FaceObservations& obs,
                                        const ExposureGainOptions& options) {
  const size_t num_views = obs.num_views;
  const auto usable = [&](size_t k) {
    const Eigen::Vector3f& c = obs.colour[k];
    return obs.quality[k] > 0 && c.minCoeff() >= options.min_level &&
           c.maxCoeff() <= options.max_level;
  };
  // Per view, its usable entries and their faces, in face order.
  std::vector<std::vector<std::pair<size_t, size_t>>> entries_of_view(num_views);
  for (size_t f = 0; f < obs.num_faces; ++f)
    for (size_t k = obs.begin[f]; k < obs.begin[f + 1]; ++k)
      if (usable(k)) entries_of_view[obs.view[k]].emplace_back(f, k);
  std::vector<std::vector<PairEstimate>> pairs_of_view(num_views);
  Progress progress("texture: exposure", num_views);
  tbb::parallel_for(size_t{0}, num_views, [&](size_t i) {
    std::vector<std::vector<Eigen::Vector3f>> ratios(num_views);  // view i's, by the other view
    for (const auto& [f, ka] : entries_of_view[i]) {
      const Eigen::Array3f log_a = obs.colour[ka].array().log();
      for (size_t kb = ka + 1; kb < obs.begin[f + 1]; ++kb)  // the face's later views
        if (usable(kb))
          ratios[obs.view[kb]].push_back((log_a - obs.colour[kb].array().log()).matrix());
    }
    std::vector<std::pair<size_t, size_t>>().swap(entries_of_view[i]);
    std::vector<float> values;
    for (size_t j = i + 1; j < num_views; ++j) {
      const std::vector<Eigen::Vector3f>& r = ratios[j];
      if (static_cast<int>(r.size()) < options.min_shared_faces) continue;
      PairEstimate pair{i, j, static_cast<double>(r.size())};
      for (int channel = 0; channel < 3; ++channel) {
        values.resize(r.size());
        for (size_t k = 0; k < r.size(); ++k) values[k] = r[k][channel];
        std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
        pair.m[channel] = -values[values.size() / 2];
      }
      pairs_of_view[i].push_back(pair);
    }
    progress.Tick();
  });
  std::vector<PairEstimate> pairs;
  for (const std::vector<PairEstimate>& of_view : pairs_of_view)
    pairs.insert(pairs.end(), of_view.begin(), of_view.end());
  return pairs;
}

}  // namespace

std::vector<Eigen::Vector3f> EstimateExposureGains(const FaceObservations& obs,
                                                   const ExposureGainOptions& options) {
  const size_t num_views = obs.num_views;
  std::vector<Eigen::Vector3f> gains(num_views, Eigen::Vector3f::Ones());
  if (!options.enabled || num_views < 2) return gains;
  const std::vector<PairEstimate> pairs = PairEstimates(obs, options);
  if (pairs.empty()) return gains;
  for (int channel = 0; channel < 3; ++channel) {
    // Normal equations of sum_ij n_ij (x_i - x_j - m_ij)^2 + (sum_i x_i)^2, x_i = log gain_i:
    // gain_i colour_i = gain_j colour_j means x_i - x_j = -log(colour_i / colour_j) = m_ij.
    Eigen::MatrixXd A = Eigen::MatrixXd::Ones(num_views, num_views);  // the gauge term
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(num_views);
    for (const PairEstimate& pair : pairs) {
      const double n = pair.n, m = pair.m[channel];
      A(pair.i, pair.i) += n;
      A(pair.j, pair.j) += n;
      A(pair.i, pair.j) -= n;
      A(pair.j, pair.i) -= n;
      rhs[pair.i] += n * m;
      rhs[pair.j] -= n * m;
    }
    // Views without any usable pair keep gain 1 through a weak pull towards 0.
    A.diagonal().array() += 1e-3;
    const Eigen::VectorXd x = A.ldlt().solve(rhs);
    const double limit = std::log(options.max_gain);
    for (size_t v = 0; v < num_views; ++v)
      gains[v][channel] = static_cast<float>(std::exp(std::clamp(x[v], -limit, limit)));
  }
  return gains;
}

void ExposureGainOptions::Check() const {
  // A pair's estimate is a median over its shared faces: it needs at least one.
  CheckAtLeast("exposure.min_shared_faces", min_shared_faces, 1);
  // A level of 0 has no logarithm.
  CheckInHalfOpenRange("exposure.min_level", min_level, 0.0f, 255.0f);
  CheckInRange("exposure.max_level", max_level, min_level, 255.0f);
  // Gains lie in [1 / max_gain, max_gain]: below 1 the interval is empty.
  CheckAtLeast("exposure.max_gain", max_gain, 1.0);
}

}  // namespace varsfm
