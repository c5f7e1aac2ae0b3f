#include "varsfm/estimators/two_view_estimators.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <random>

#include <Eigen/Geometry>

#include "varsfm/estimators/essential_5pt.h"
#include "varsfm/estimators/fundamental_7pt.h"
#include "varsfm/estimators/fundamental_8pt.h"
#include "varsfm/estimators/fundamental_degeneracy.h"
#include "varsfm/estimators/homography_4pt.h"
#include "varsfm/geometry/essential.h"
#include "varsfm/geometry/fundamental.h"

namespace varsfm {
namespace {

void Gather(const std::vector<Eigen::Vector2d>& x1, const std::vector<Eigen::Vector2d>& x2,
            const std::vector<int>& indices, std::vector<Eigen::Vector2d>* y1,
            std::vector<Eigen::Vector2d>* y2) {
  y1->resize(indices.size());
  y2->resize(indices.size());
  for (size_t k = 0; k < indices.size(); ++k) {
    (*y1)[k] = x1[indices[k]];
    (*y2)[k] = x2[indices[k]];
  }
}

}  // namespace

template <TwoViewModel kModel>
void TwoViewEstimator<kModel>::MinimalSolve(const std::vector<int>& sample,
                                            std::vector<Model>* models) const {
  std::vector<Eigen::Vector2d> y1, y2;
  Gather(x1, x2, sample, &y1, &y2);
  if constexpr (kModel == TwoViewModel::kHomography) {
    Eigen::Matrix3d H;
    if (Homography4pt(y1, y2, &H)) models->push_back(H);
  } else if constexpr (kModel == TwoViewModel::kFundamental) {
    // Solutions that would put part of their own sample behind the cameras are no epipolar
    // geometry of the scene (SatisfiesOrientedEpipolarConstraint): dropped before they are
    // scored, as OpenCV's USAC drops them.
    const auto first = static_cast<std::ptrdiff_t>(models->size());
    Fundamental7pt(y1, y2, models);
    models->erase(std::remove_if(models->begin() + first, models->end(),
                                 [&](const Model& F) {
                                   return !SatisfiesOrientedEpipolarConstraint(F, y1, y2);
                                 }),
                  models->end());
  } else {
    Essential5pt(y1, y2, models);
  }
}

template <TwoViewModel kModel>
void TwoViewEstimator<kModel>::NonMinimalSolve(const std::vector<int>& indices,
                                               const Model& /*initial*/,
                                               std::vector<Model>* models) const {
  // E's linear solver is the eight-point one; LO is skipped below eight correspondences.
  if (kModel == TwoViewModel::kEssential && indices.size() < 8) return;
  std::vector<Eigen::Vector2d> y1, y2;
  Gather(x1, x2, indices, &y1, &y2);
  Eigen::Matrix3d M;
  if constexpr (kModel == TwoViewModel::kHomography) {
    if (HomographyDLT(y1, y2, &M)) models->push_back(M);
  } else if (Fundamental8pt(y1, y2, &M)) {
    models->push_back(kModel == TwoViewModel::kEssential ? ProjectToEssential(M) : M);
  }
}

template <TwoViewModel kModel>
double TwoViewEstimator<kModel>::SquaredResidual(const Model& model, size_t i) const {
  if constexpr (kModel == TwoViewModel::kHomography) {
    const Eigen::Vector3d y = model * x1[i].homogeneous();
    if (y.z() == 0) return std::numeric_limits<double>::infinity();
    return (y.hnormalized() - x2[i]).squaredNorm();
  } else {
    return SampsonErrorSquared(model, x1[i], x2[i]);
  }
}

template <TwoViewModel kModel>
void TwoViewEstimator<kModel>::DegeneracyModels(const std::vector<int>& sample, const Model& model,
                                                const RansacOptions& options, Rng* rng,
                                                std::vector<Model>* models) const
    requires(kModel == TwoViewModel::kFundamental) {
  const double threshold2 = options.max_error * options.max_error;
  std::vector<Eigen::Vector2d> y1, y2;
  Gather(x1, x2, sample, &y1, &y2);
  Eigen::Matrix3d H;
  // The test's homography comes exact through three noisy points and carries the sample's other
  // plane points less well than one fitted to many: tested at twice the threshold (a false
  // alarm costs only the recovery's time; its models must still score better).
  if (!FindDominantPlane(model, y1, y2, 4 * threshold2, &H)) return;
  // The plane's homography from three correspondences carries their noise: refitted by least
  // squares on the data it carries, from twice the threshold down to it (as the local
  // optimisation of Lebeda et al. does), kept while it carries more.
  const HomographyEstimator plane{x1, x2};
  std::vector<int> on_plane;
  ransac_internal::Inliers(plane, H, threshold2, &on_plane);
  for (const double factor : {4.0, 1.0, 1.0}) {
    std::vector<int> support;
    ransac_internal::Inliers(plane, H, factor * threshold2, &support);
    std::vector<Model> refit;
    if (support.size() >= 8) plane.NonMinimalSolve(support, H, &refit);
    if (refit.empty()) break;
    std::vector<int> refit_on_plane;
    ransac_internal::Inliers(plane, refit.front(), threshold2, &refit_on_plane);
    if (refit_on_plane.size() <= on_plane.size()) break;
    H = refit.front();
    on_plane.swap(refit_on_plane);
  }
  // The data off the plane: the complement of on_plane (ascending, as Inliers lists them).
  std::vector<int> off_plane;
  for (int i = 0, next = 0; i < static_cast<int>(x1.size()); ++i) {
    if (next < static_cast<int>(on_plane.size()) && on_plane[next] == i)
      ++next;
    else
      off_plane.push_back(i);
  }
  if (off_plane.size() < 2) return;
  // Every F = [e2]x H carries the plane's data (x2 ~ H x1 lies on the line e2 x x2), so the
  // candidates are ranked by their MSAC cost over the data off the plane alone.
  std::uniform_int_distribution<size_t> pick(0, off_plane.size() - 1);
  double best_cost = std::numeric_limits<double>::infinity();
  Model best_model;
  int required = options.degeneracy_max_trials;
  for (int trial = 0; trial < required; ++trial) {
    const size_t a = pick(*rng), b = pick(*rng);
    Model F;
    if (a == b || !FundamentalFromPlaneAndParallax(H, x1[off_plane[a]], x2[off_plane[a]],
                                                   x1[off_plane[b]], x2[off_plane[b]], &F))
      continue;
    double cost = 0;
    size_t parallax_inliers = 0;
    for (const int i : off_plane) {
      const double r2 = SquaredResidual(F, i);
      parallax_inliers += r2 < threshold2;
      cost += std::min(r2, threshold2);
      if (!(cost < best_cost)) break;
    }
    if (!(cost < best_cost)) continue;
    best_cost = cost;
    best_model = F;
    required = ransac_internal::RequiredIterations(
        parallax_inliers, off_plane.size(), 2, options.confidence, options.degeneracy_min_trials,
        options.degeneracy_max_trials);
  }
  if (!std::isfinite(best_cost)) return;
  // F from a homography fitted to three points and two more points is rough: its least-squares
  // refit on its inliers (which now hold the data off the plane) is offered beside it, as the
  // local optimisation would do with a new best model.
  models->push_back(best_model);
  std::vector<int> inliers;
  ransac_internal::Inliers(*this, best_model, threshold2, &inliers);
  if (inliers.size() >= 8) NonMinimalSolve(inliers, best_model, models);
}

template struct TwoViewEstimator<TwoViewModel::kFundamental>;
template struct TwoViewEstimator<TwoViewModel::kHomography>;
template struct TwoViewEstimator<TwoViewModel::kEssential>;

RansacReport<Eigen::Matrix3d> EstimateFundamentalMatrix(const std::vector<Eigen::Vector2d>& x1,
                                                        const std::vector<Eigen::Vector2d>& x2,
                                                        const RansacOptions& options,
                                                        const NeighbourhoodGraph* neighbourhood) {
  if (x1.size() != x2.size()) return {};
  return Ransac(FundamentalEstimator{x1, x2}, options, neighbourhood);
}

RansacReport<Eigen::Matrix3d> EstimateHomography(const std::vector<Eigen::Vector2d>& x1,
                                                 const std::vector<Eigen::Vector2d>& x2,
                                                 const RansacOptions& options,
                                                 const NeighbourhoodGraph* neighbourhood) {
  if (x1.size() != x2.size()) return {};
  return Ransac(HomographyEstimator{x1, x2}, options, neighbourhood);
}

RansacReport<Eigen::Matrix3d> EstimateEssentialMatrix(const std::vector<Eigen::Vector2d>& x1,
                                                      const std::vector<Eigen::Vector2d>& x2,
                                                      const RansacOptions& options) {
  if (x1.size() != x2.size()) return {};
  return Ransac(EssentialEstimator{x1, x2}, options);
}

}  // namespace varsfm
