#pragma once
// Shared synthetic data for the estimator tests.
#include <vector>

#include <Eigen/Core>

#include "varsfm/synthetic/synthetic_scene.h"

namespace varsfm::testing {

// Three views of a box of 2000 points, zooming from f = 800 to 2000 px, principal points off
// centre by up to 25 px.
inline SyntheticOptions ZoomBox() {
  SyntheticOptions o;
  o.num_images = 3;
  o.num_points = 2000;
  o.focal_start = 800;
  o.focal_end = 2000;
  o.principal_point_offset = 25;
  return o;
}

struct Matches {
  std::vector<Eigen::Vector2d> x1, x2;
  std::vector<char> outlier;  // ground-truth outlier flag (either observation is an outlier)
};

inline Matches PairMatches(const SyntheticScene& scene, int i, int j) {
  Matches m;
  std::vector<int> ids;
  scene.Correspondences(i, j, &m.x1, &m.x2, &ids);
  std::vector<char> out_i(scene.points.size(), 0), out_j(scene.points.size(), 0);
  for (const auto& o : scene.observations[i]) out_i[o.point_id] = o.outlier;
  for (const auto& o : scene.observations[j]) out_j[o.point_id] = o.outlier;
  for (const int id : ids) m.outlier.push_back(out_i[id] || out_j[id]);
  return m;
}

// Recall and precision of an inlier mask against the ground-truth flags.
inline void InlierQuality(const std::vector<char>& mask, const std::vector<char>& outlier,
                          double* recall, double* precision) {
  int tp = 0, fp = 0, fn = 0;
  for (size_t k = 0; k < mask.size(); ++k) {
    if (mask[k] && !outlier[k]) ++tp;
    if (mask[k] && outlier[k]) ++fp;
    if (!mask[k] && !outlier[k]) ++fn;
  }
  *recall = tp / static_cast<double>(tp + fn);
  *precision = tp / static_cast<double>(tp + fp);
}

// A one-parameter model, a shift along x: small enough to check a labelling against its energy
// by enumeration, or RANSAC's choices by hand.
struct ShiftEstimator {
  using Model = double;
  static constexpr int kMinSampleSize = 1;
  std::vector<double> x;
  size_t NumData() const { return x.size(); }
  void MinimalSolve(const std::vector<int>& s, std::vector<Model>* m) const {
    m->push_back(x[s[0]]);
  }
  void NonMinimalSolve(const std::vector<int>& s, const Model&, std::vector<Model>* m) const {
    double sum = 0;
    for (const int i : s) sum += x[i];
    m->push_back(sum / static_cast<double>(s.size()));
  }
  double SquaredResidual(const Model& model, size_t i) const {
    return (x[i] - model) * (x[i] - model);
  }
};

}  // namespace varsfm::testing
