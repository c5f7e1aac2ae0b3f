// The checks of the mapper's own options (incremental_mapper.h) and of the initial pair's
// (initial_pair.h); each other part checks its own where it is defined.
#include <cmath>

#include "varsfm/sfm/incremental_mapper.h"
#include "varsfm/sfm/initial_pair.h"
#include "varsfm/util/option_check.h"

namespace varsfm {

void InitialPairOptions::Check() const {
  CheckAtLeast("min_num_matches", min_num_matches, 1);
  CheckFraction("min_matches_fraction", min_matches_fraction);
}

void IncrementalMapperOptions::Check() const {
  initial_pair.Check();
  CheckAtLeast("max_initial_pair_trials", max_initial_pair_trials, 1);
  CheckAtLeast("min_initial_points", min_initial_points, 1);
  CheckInRange("init_min_median_angle_deg", init_min_median_angle_deg, 0, 180);
  CheckPositive("init_max_error_px", init_max_error_px);
  CheckPositive("degenerate_focal_log_step", degenerate_focal_log_step);
  CheckAtLeast("degenerate_focal_max_steps", degenerate_focal_max_steps, 1);
  registration.Check();
  triangulation.Check();
  adjustment.Check();
  intrinsics.Check();
  CheckNonNegative("--threads", num_threads);
}

}  // namespace varsfm
