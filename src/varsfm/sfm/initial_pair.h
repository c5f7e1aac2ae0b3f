#pragma once
// Choice of the two images the reconstruction starts from (El Hazzat et al., section 3.4): many
// matches and a large camera motion. The paper's disparity-matrix criterion: for candidate pairs,
// D_M = mean and D_S = standard deviation of the match disparities |x2 - x1| (normalised by the
// image diagonal); the pair maximising (D_M / max D_M) * (D_S / max D_S) is chosen. A large mean
// says the camera moved; a large spread says the disparities vary with depth, i.e. there is
// parallax rather than a rotation or a plane (both give smooth, homography-like disparities).
// varsfm adds what the criterion alone misses: a minimum number of verified matches, and pairs
// the matcher flagged as planar/panoramic (explained by a homography) are never candidates.
#include <string>
#include <vector>

#include "varsfm/scene/reconstruction.h"
#include "varsfm/sfm/correspondence_graph.h"

namespace varsfm {

struct InitialPairOptions {
  int min_num_matches = 100;
  // Candidates need at least this fraction of the best pair's match count ("many matches").
  double min_matches_fraction = 0.25;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

struct InitialPairCandidate {
  image_t image_id1 = kInvalidImageId;
  image_t image_id2 = kInvalidImageId;
  size_t num_matches = 0;
  double disparity_mean = 0;  // D_M, fraction of the image diagonal
  double disparity_std = 0;   // D_S
  double score = 0;           // normalised D_M * D_S
};

// Whether Bougnoux's closed-form focal lengths from F (principal points at the image centres)
// can be trusted: positive, in [0.3, 5] x max(w, h), and stable when a principal point moves by
// 2 % of the image size. Near-coplanar optical axes (common when every photo looks at the same
// object) fail the last test. Cheap: used to prefer such pairs before calibrating one.
bool ClosedFormFocalsWellConditioned(const Eigen::Matrix3d& F, int width1, int height1, int width2,
                                     int height2);

// One try at initialising: candidate `candidate` (an index into RankInitialPairs' list), and
// whether a degenerate self-calibration is accepted (focal lengths from the prior and a third
// view; IncrementalMapper::SelectDegenerateFocal).
struct InitialPairAttempt {
  int candidate = 0;
  bool accept_degenerate = false;
};

// The order in which ranked candidates are tried, the first that initialises winning: those
// whose closed-form focal lengths are well-conditioned, then the others, each refusing a
// degenerate calibration (the conditioning is a cheap proxy, the calibration's own tests decide);
// then every candidate accepting one. A pair whose calibration is degenerate is a last resort
// even when it ranks first: the model grown from the prior's focal length can settle in another
// minimum (bench/results/2026-12-04-s15-initial-pair.md). Candidate k takes part when usable[k].
std::vector<InitialPairAttempt> InitialPairAttempts(const std::vector<bool>& usable,
                                                    const std::vector<bool>& well_conditioned);

// Candidates sorted by decreasing score. `excluded_pairs` (planar/panoramic pairs) and
// `registered` images are skipped. Deterministic: ties broken by image ids.
std::vector<InitialPairCandidate> RankInitialPairs(
    const Reconstruction& reconstruction, const CorrespondenceGraph& graph,
    const std::vector<std::pair<image_t, image_t>>& excluded_pairs,
    const InitialPairOptions& options);

// Why RankInitialPairs found no candidate, in one line for the user: every pair explained by a
// homography (no parallax: a rotation about the camera centre, or a planar scene), or too few
// matches in the pairs that are not.
std::string NoInitialPairReason(const CorrespondenceGraph& graph,
                                const std::vector<std::pair<image_t, image_t>>& excluded_pairs,
                                const InitialPairOptions& options);

}  // namespace varsfm
