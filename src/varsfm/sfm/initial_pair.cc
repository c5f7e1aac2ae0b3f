#include "varsfm/sfm/initial_pair.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include <fmt/format.h>

#include "varsfm/calibration/bougnoux.h"

namespace varsfm {

bool ClosedFormFocalsWellConditioned(const Eigen::Matrix3d& F, int width1, int height1, int width2,
                                     int height2) {
  constexpr double kPerturbation = 0.02;  // of the image size
  constexpr double kMaxLogChange = 0.15;  // |log f' - log f|
  const Eigen::Vector2d pp1(width1 / 2.0, height1 / 2.0), pp2(width2 / 2.0, height2 / 2.0);
  const double size1 = std::max(width1, height1), size2 = std::max(width2, height2);
  const auto focals = BougnouxFocalLengths(F, pp1, pp2);
  if (!focals || focals->first < 0.3 * size1 || focals->first > 5 * size1 ||
      focals->second < 0.3 * size2 || focals->second > 5 * size2)
    return false;
  for (const Eigen::Vector2d& dir : {Eigen::Vector2d(1, 0), Eigen::Vector2d(0, 1),
                                     Eigen::Vector2d(-1, 0), Eigen::Vector2d(0, -1)}) {
    for (int which = 0; which < 2; ++which) {
      const auto moved =
          BougnouxFocalLengths(F, pp1 + (which == 0 ? kPerturbation * size1 : 0.0) * dir,
                               pp2 + (which == 1 ? kPerturbation * size2 : 0.0) * dir);
      if (!moved || std::abs(std::log(moved->first / focals->first)) > kMaxLogChange ||
          std::abs(std::log(moved->second / focals->second)) > kMaxLogChange)
        return false;
    }
  }
  return true;
}

std::vector<InitialPairCandidate> RankInitialPairs(
    const Reconstruction& rec, const CorrespondenceGraph& graph,
    const std::vector<std::pair<image_t, image_t>>& excluded_pairs,
    const InitialPairOptions& options) {
  const std::set<std::pair<image_t, image_t>> excluded(excluded_pairs.begin(),
                                                       excluded_pairs.end());
  size_t max_matches = 0;
  for (const auto& [pair, count] : graph.PairCounts())
    if (!excluded.count(pair)) max_matches = std::max(max_matches, count);
  const size_t min_matches = std::max<size_t>(
      options.min_num_matches, static_cast<size_t>(options.min_matches_fraction * max_matches));

  std::vector<InitialPairCandidate> candidates;
  for (const auto& [pair, count] : graph.PairCounts()) {
    if (count < min_matches || excluded.count(pair)) continue;
    const auto [id1, id2] = pair;
    const Image& image1 = rec.image(id1);
    const Image& image2 = rec.image(id2);
    const Camera& camera1 = rec.CameraOf(id1);
    const double diagonal = std::hypot(camera1.width, camera1.height);
    // Disparity of each match, as in the paper's disparity matrix (eqs. 6-7).
    double sum = 0, sum_sq = 0;
    const FeatureMatches matches = graph.MatchesBetween(id1, id2);
    for (const auto& m : matches) {
      const double d =
          (image2.points2D[m.point2D_idx2].xy - image1.points2D[m.point2D_idx1].xy).norm() /
          diagonal;
      sum += d;
      sum_sq += d * d;
    }
    const double n = static_cast<double>(matches.size());
    InitialPairCandidate c;
    c.image_id1 = id1;
    c.image_id2 = id2;
    c.num_matches = matches.size();
    c.disparity_mean = sum / n;
    c.disparity_std = std::sqrt(std::max(0.0, sum_sq / n - c.disparity_mean * c.disparity_mean));
    candidates.push_back(c);
  }
  double max_mean = 0, max_std = 0;
  for (const auto& c : candidates) {
    max_mean = std::max(max_mean, c.disparity_mean);
    max_std = std::max(max_std, c.disparity_std);
  }
  for (auto& c : candidates)
    c.score = (max_mean > 0 ? c.disparity_mean / max_mean : 0) *
              (max_std > 0 ? c.disparity_std / max_std : 0);
  std::sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) {
    if (a.score != b.score) return a.score > b.score;
    return std::tie(a.image_id1, a.image_id2) < std::tie(b.image_id1, b.image_id2);
  });
  return candidates;
}

std::string NoInitialPairReason(const CorrespondenceGraph& graph,
                                const std::vector<std::pair<image_t, image_t>>& excluded_pairs,
                                const InitialPairOptions& options) {
  const std::set<std::pair<image_t, image_t>> excluded(excluded_pairs.begin(),
                                                       excluded_pairs.end());
  size_t num_excluded = 0, most_matches = 0;
  for (const auto& [pair, count] : graph.PairCounts()) {
    if (excluded.count(pair)) {
      ++num_excluded;
    } else {
      most_matches = std::max(most_matches, count);
    }
  }
  const size_t num_pairs = graph.PairCounts().size();
  if (num_pairs > 0 && num_excluded == num_pairs)
    return fmt::format(
        "all {} verified image pairs are related by a homography (the camera rotated about its "
        "centre, or the scene is a plane): there is no parallax to reconstruct from",
        num_pairs);
  return fmt::format(
      "no image pair has enough verified matches to initialise the reconstruction (the best "
      "has {}, {} are needed; {} of {} pairs are related by a homography)",
      most_matches, options.min_num_matches, num_excluded, num_pairs);
}

std::vector<InitialPairAttempt> InitialPairAttempts(const std::vector<bool>& usable,
                                                    const std::vector<bool>& well_conditioned) {
  std::vector<InitialPairAttempt> attempts;
  const int n = static_cast<int>(usable.size());
  for (const bool conditioned : {true, false})
    for (int k = 0; k < n; ++k)
      if (usable[k] && well_conditioned[k] == conditioned) attempts.push_back({k, false});
  for (int k = 0; k < n; ++k)
    if (usable[k]) attempts.push_back({k, true});
  return attempts;
}

}  // namespace varsfm
