#pragma once
// Per-image exposure (and white balance): one gain per colour channel and photo, so that faces
// seen by several photos get the same colour from each once the gains are applied. Photos of
// one scene taken with automatic exposure differ by tens of percent; without this, neighbouring
// faces textured from different photos form a patchwork (the global levelling of
// colour_levelling.h then only has the residual, local differences left to remove).
//
// For every pair of photos, the median over the faces both see of log(colour_i / colour_j) is a
// robust estimate of log(gain_j / gain_i) (occluders and misregistered faces are a minority);
// the gains are the least-squares fit to these pairwise estimates, each weighted by its number
// of faces, with the geometric mean gain fixed to 1.
#include <vector>

#include <Eigen/Core>

#include "varsfm/texture/face_observations.h"

namespace varsfm {

struct ExposureGainOptions {
  bool enabled = true;
  // Pairs sharing fewer faces than this are not used.
  int min_shared_faces = 50;
  // Mean colours outside (dark, saturated) are not used: they are not proportional to exposure.
  float min_level = 8, max_level = 245;
  // Gains are clamped to [1 / max_gain, max_gain].
  double max_gain = 4.0;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

// One BGR gain per view; all 1 when disabled or nothing overlaps.
std::vector<Eigen::Vector3f> EstimateExposureGains(const FaceObservations& observations,
                                                   const ExposureGainOptions& options = {});

}  // namespace varsfm
