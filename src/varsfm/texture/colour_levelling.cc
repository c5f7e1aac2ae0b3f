#include "varsfm/texture/colour_levelling.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include <tbb/parallel_for.h>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "varsfm/texture/face_adjacency.h"
#include "varsfm/util/log.h"
#include "varsfm/util/option_check.h"
#include "varsfm/util/timer.h"

namespace varsfm {
namespace {

// Image `view`'s colour (after its gain) where world point x projects; false when behind it.
bool ColourAt(const PosedCamera& view, const cv::Mat& small, double scale,
              const Eigen::Vector3f& gain, const Eigen::Vector3d& x, Eigen::Vector3f* colour) {
  const Eigen::Vector3d in_camera = view.cam_from_world * x;
  if (in_camera.z() <= 0) return false;
  *colour = SampleBilinear(small, view.camera.Project(in_camera) * scale).cwiseProduct(gain);
  return true;
}

struct SeamSample {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double weight = 0;
};

// The levelling's normal equations (SPD: the ridge): by sparse Cholesky, or beyond
// direct_max_unknowns by conjugate gradients, where the factor's fill on a large model's mesh
// made the direct solve slow (docs/measurements.md). The ridge bounds the system's
// condition number (about (ridge + the smoothness and seam weights at a corner) / ridge), so
// the iterations are few.
Eigen::MatrixXd SolveNormalEquations(const Eigen::SparseMatrix<double>& normal,
                                     const Eigen::MatrixXd& rhs,
                                     const ColourLevellingOptions& options) {
  const Timer timer;
  const bool direct = normal.rows() <= options.direct_max_unknowns;
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(rhs.rows(), rhs.cols());
  if (direct) {
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(normal);
    if (solver.info() == Eigen::Success) g = solver.solve(rhs);  // fails never: SPD by the ridge
  } else {
    // The channels are independent systems: solved side by side, a solver each (a solve
    // records its iterations in the solver).
    tbb::parallel_for(0, static_cast<int>(rhs.cols()), [&](int c) {
      Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> solver;
      solver.setTolerance(options.iterative_tolerance);
      solver.compute(normal);
      g.col(c) = solver.solve(rhs.col(c));
    });
  }
  debug("texture: levelling solved for {} unknowns ({}) in {:.1f} s", normal.rows(),
        direct ? "sparse Cholesky" : "conjugate gradients", timer.Seconds());
  return g;
}

}  // namespace

std::vector<std::array<Eigen::Vector3f, 3>> LevelColours(
    const std::vector<Eigen::Vector3d>& vertices, const std::vector<Eigen::Vector3i>& faces,
    const std::vector<int>& labels, const std::vector<PosedCamera>& views,
    const std::vector<cv::Mat>& small_photos, const std::vector<double>& small_scale,
    const std::vector<Eigen::Vector3f>& gains, const ColourLevellingOptions& options) {
  std::vector<std::array<Eigen::Vector3f, 3>> corrections(
      faces.size(), {Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero()});
  if (!options.enabled) return corrections;
  const uint64_t num_views = views.size();
  const auto key = [&](int vertex, int label) {
    return static_cast<uint64_t>(vertex) * num_views + static_cast<uint64_t>(label);
  };
  // One unknown per (vertex, label) of a labelled face's corner, numbered in face order.
  std::unordered_map<uint64_t, int> unknown_of;
  std::vector<std::array<int, 3>> corner_unknown(faces.size(), {-1, -1, -1});
  for (size_t f = 0; f < faces.size(); ++f) {
    if (labels[f] < 0) continue;
    for (int k = 0; k < 3; ++k)
      corner_unknown[f][k] =
          unknown_of.try_emplace(key(faces[f][k], labels[f]), static_cast<int>(unknown_of.size()))
              .first->second;
  }
  const int n = static_cast<int>(unknown_of.size());
  if (n == 0) return corrections;

  // Seam colours f_(v,l), sampled along every edge between faces of different labels.
  std::unordered_map<uint64_t, SeamSample> seam;
  std::vector<int> seam_vertices;
  const std::vector<std::array<int, 3>> neighbours = FaceNeighbours(faces);
  for (size_t f = 0; f < faces.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int g = neighbours[f][k];
      if (g <= static_cast<int>(f) || labels[f] < 0 || labels[g] < 0 || labels[f] == labels[g])
        continue;
      const int a = faces[f][k], b = faces[f][(k + 1) % 3];
      const int edge_labels[2] = {labels[f], labels[g]};
      const Eigen::Vector3d pa = vertices[a], pb = vertices[b];
      // As many samples as the edge covers pixels of the small photo (at least 2).
      const PosedCamera& first = views[edge_labels[0]];
      const double length_px = (first.camera.Project(first.cam_from_world * pa) -
                                first.camera.Project(first.cam_from_world * pb))
                                   .norm() *
                               small_scale[edge_labels[0]];
      const int samples =
          std::clamp(static_cast<int>(std::ceil(std::isfinite(length_px) ? length_px : 2)), 2,
                     options.max_samples_per_edge);
      for (int s = 0; s < samples; ++s) {
        const double t = (s + 0.5) / samples;
        const Eigen::Vector3d x = pa + t * (pb - pa);
        Eigen::Vector3f c[2];
        if (!ColourAt(views[edge_labels[0]], small_photos[edge_labels[0]],
                      small_scale[edge_labels[0]], gains[edge_labels[0]], x, &c[0]) ||
            !ColourAt(views[edge_labels[1]], small_photos[edge_labels[1]],
                      small_scale[edge_labels[1]], gains[edge_labels[1]], x, &c[1]))
          continue;
        for (int side = 0; side < 2; ++side) {
          for (const auto& [vertex, w] : {std::pair{a, 1 - t}, std::pair{b, t}}) {
            SeamSample& sample = seam[key(vertex, edge_labels[side])];
            sample.sum += w * c[side].cast<double>();
            sample.weight += w;
          }
        }
      }
      seam_vertices.push_back(a);
      seam_vertices.push_back(b);
    }
  }
  std::sort(seam_vertices.begin(), seam_vertices.end());
  seam_vertices.erase(std::unique(seam_vertices.begin(), seam_vertices.end()), seam_vertices.end());

  // Normal equations of the three terms, assembled directly.
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, 3);
  const auto add_difference = [&](int i, int j, double weight, const Eigen::Vector3d& target) {
    // weight x (x_i - x_j - target)^2
    triplets.emplace_back(i, i, weight);
    triplets.emplace_back(j, j, weight);
    triplets.emplace_back(i, j, -weight);
    triplets.emplace_back(j, i, -weight);
    rhs.row(i) += weight * target.transpose();
    rhs.row(j) -= weight * target.transpose();
  };
  // The seam samples by vertex, each vertex's in label order (its keys, sorted): a look-up of
  // every label at every seam vertex grew with the photos times the seam.
  std::vector<std::pair<uint64_t, const SeamSample*>> by_key;
  by_key.reserve(seam.size());
  for (const auto& [k, sample] : seam) by_key.emplace_back(k, &sample);
  std::sort(by_key.begin(), by_key.end());
  size_t next_key = 0;
  std::vector<std::pair<int, Eigen::Vector3d>> at_vertex;  // (unknown, seam colour)
  for (const int v : seam_vertices) {
    at_vertex.clear();
    for (; next_key < by_key.size() && by_key[next_key].first / num_views == uint64_t(v);
         ++next_key) {
      const auto& [k, s] = by_key[next_key];
      const auto u = unknown_of.find(k);
      if (u == unknown_of.end() || s->weight <= 0) continue;
      at_vertex.emplace_back(u->second, s->sum / s->weight);
    }
    // g_l1 - g_l2 = f_l2 - f_l1 for every pair of images meeting at v, unless they differ by
    // more than exposure can explain once the gains are applied: then one of them shows
    // something else there (an occluder's edge, a misregistered detail), and closing that gap
    // would spread a false colour over the whole chart.
    for (size_t i = 0; i < at_vertex.size(); ++i)
      for (size_t j = i + 1; j < at_vertex.size(); ++j) {
        const Eigen::Vector3d gap = at_vertex[j].second - at_vertex[i].second;
        if (gap.norm() <= options.max_seam_difference)
          add_difference(at_vertex[i].first, at_vertex[j].first, 1.0, gap);
      }
  }
  for (size_t f = 0; f < faces.size(); ++f) {
    if (labels[f] < 0) continue;
    for (int k = 0; k < 3; ++k)
      add_difference(corner_unknown[f][k], corner_unknown[f][(k + 1) % 3], options.smoothness,
                     Eigen::Vector3d::Zero());
  }
  for (int i = 0; i < n; ++i) triplets.emplace_back(i, i, options.ridge);
  info("texture: levelling colours across the seams at {} vertices ({} corrections)",
       seam_vertices.size(), n);
  Eigen::SparseMatrix<double> normal(n, n);
  normal.setFromTriplets(triplets.begin(), triplets.end());
  const Eigen::MatrixXd g = SolveNormalEquations(normal, rhs, options);
  for (size_t f = 0; f < faces.size(); ++f) {
    if (labels[f] < 0) continue;
    for (int k = 0; k < 3; ++k) corrections[f][k] = g.row(corner_unknown[f][k]).cast<float>();
  }
  return corrections;
}

void ColourLevellingOptions::Check() const {
  CheckNonNegative("levelling.smoothness", smoothness);
  CheckPositive("levelling.ridge", ridge);
  CheckPositive("levelling.max_seam_difference", max_seam_difference);
  CheckAtLeast("levelling.max_samples_per_edge", max_samples_per_edge, 1);
  CheckNonNegative("levelling.direct_max_unknowns", direct_max_unknowns);
  CheckPositive("levelling.iterative_tolerance", iterative_tolerance);
}

}  // namespace varsfm
