// The mapper's option checks (incremental_mapper.h, initial_pair.h), apart from the mapper's
// algorithm.
#include <cmath>

#include "varsfm/sfm/incremental_mapper.h"
#include "varsfm/sfm/initial_pair.h"
#include "varsfm/util/option_check.h"

namespace varsfm {

void InitialPairOptions::Check() const {
  CheckAtLeast("min_num_matches", min_num_matches, 1);
  CheckInRange("min_matches_fraction", min_matches_fraction, 0, 1);
}

void IncrementalMapperOptions::Check() const {
  initial_pair.Check();
  CheckAtLeast("max_initial_pair_trials", max_initial_pair_trials, 1);
  CheckAtLeast("min_initial_points", min_initial_points, 1);
  CheckInRange("init_min_median_angle_deg", init_min_median_angle_deg, 0, 180);
  CheckAtLeast("--local-ba-images", local_ba_images, 1);
  CheckAtLeast("--local-ba-max-track", local_ba_max_track_length, 0);
  CheckGreaterThan("local_ba_function_tolerance", local_ba_function_tolerance, 0);
  CheckGreaterThan("--global-ba-tolerance", global_ba_function_tolerance, 0);
  CheckGreaterThan("--growth-ba-tolerance", growth_ba_function_tolerance, 0);
  CheckAtLeast("global_ba_max_iterations", global_ba_max_iterations, 1);
  CheckAtLeast("--degenerate-init-global-ba", degenerate_init_global_ba_images, 0);
  CheckAtLeast("final_global_ba_max_iterations", final_global_ba_max_iterations, 1);
  CheckAtLeast("--global-ba-images", first_global_ba_images, 0);
  // A factor of 1 or less would run a global adjustment after every image; 0 says "never".
  if (global_ba_growth != 0 && !(std::isfinite(global_ba_growth) && global_ba_growth > 1))
    FailOption("--global-ba-growth", "0 (never) or a number > 1", global_ba_growth);
  CheckAtLeast("--min-correspondences", min_correspondences, 6);
  CheckAtLeast("min_registration_inliers", min_registration_inliers, 6);
  CheckGreaterThan("registration_max_error_px", registration_max_error_px, 0);
  CheckGreaterThan("triangulation_max_error_px", triangulation_max_error_px, 0);
  CheckGreaterThan("filter_max_error_px", filter_max_error_px, 0);
  CheckInRange("min_triangulation_angle_deg", min_triangulation_angle_deg, 0, 180);
  CheckAtLeast("--threads", num_threads, 0);
}

}  // namespace varsfm
