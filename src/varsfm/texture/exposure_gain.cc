#include "varsfm/texture/exposure_gain.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "varsfm/util/option_check.h"

namespace varsfm {

std::vector<Eigen::Vector3f> EstimateExposureGains(const FaceObservations& obs,
                                                   const ExposureGainOptions& options) {
  const size_t num_views = obs.num_views;
  std::vector<Eigen::Vector3f> gains(num_views, Eigen::Vector3f::Ones());
  if (!options.enabled || num_views < 2) return gains;
  const auto usable = [&](const Eigen::Vector3f& c) {
    return c.minCoeff() >= options.min_level && c.maxCoeff() <= options.max_level;
  };
  // Log-ratios per ordered pair (i < j) and channel.
  std::vector<std::vector<Eigen::Vector3f>> ratios(num_views * num_views);
  std::vector<int> seen;
  for (size_t f = 0; f < obs.num_faces; ++f) {
    seen.clear();
    for (size_t v = 0; v < num_views; ++v)
      if (obs.Quality(v, f) > 0 && usable(obs.Colour(v, f))) seen.push_back(static_cast<int>(v));
    for (size_t a = 0; a < seen.size(); ++a)
      for (size_t b = a + 1; b < seen.size(); ++b)
        ratios[seen[a] * num_views + seen[b]].push_back(
            (obs.Colour(seen[a], f).array().log() - obs.Colour(seen[b], f).array().log()).matrix());
  }
  for (int channel = 0; channel < 3; ++channel) {
    // Normal equations of sum_ij n_ij (x_i - x_j - m_ij)^2 + (sum_i x_i)^2, x_i = log gain_i:
    // gain_i colour_i = gain_j colour_j means x_i - x_j = -log(colour_i / colour_j) = m_ij.
    Eigen::MatrixXd A = Eigen::MatrixXd::Ones(num_views, num_views);  // the gauge term
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(num_views);
    bool any = false;
    for (size_t i = 0; i < num_views; ++i) {
      for (size_t j = i + 1; j < num_views; ++j) {
        std::vector<Eigen::Vector3f>& r = ratios[i * num_views + j];
        if (static_cast<int>(r.size()) < options.min_shared_faces) continue;
        std::vector<float> values(r.size());
        for (size_t k = 0; k < r.size(); ++k) values[k] = r[k][channel];
        std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
        const double m = -values[values.size() / 2];
        const double n = static_cast<double>(r.size());
        A(i, i) += n;
        A(j, j) += n;
        A(i, j) -= n;
        A(j, i) -= n;
        rhs[i] += n * m;
        rhs[j] -= n * m;
        any = true;
      }
    }
    if (!any) return gains;
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
