#include "varsfm/sfm/bundle_adjustment_schedule.h"

#include <cmath>

#include "varsfm/util/option_check.h"

namespace varsfm {

void BundleAdjustmentScheduleOptions::Check() const {
  CheckAtLeast("--local-ba-images", local_ba_images, 1);
  CheckNonNegative("--local-ba-max-track", local_ba_max_track_length);
  CheckAtLeast("local_ba_max_iterations", local_ba_max_iterations, 1);
  CheckPositive("local_ba_function_tolerance", local_ba_function_tolerance);
  CheckNonNegative("--global-ba-images", first_global_ba_images);
  // A factor of 1 or less would run a global adjustment after every image; 0 says "never".
  if (global_ba_growth != 0 && !(std::isfinite(global_ba_growth) && global_ba_growth > 1))
    FailOption("--global-ba-growth", "0 (never) or a number > 1", global_ba_growth);
  CheckPositive("--global-ba-tolerance", global_ba_function_tolerance);
  CheckPositive("--growth-ba-tolerance", growth_ba_function_tolerance);
  CheckNonNegative("--two-view-filter", final_two_view_filter_factor);
  if (global_ba_trust_region != BundleAdjustmentOptions::TrustRegion::kDogleg &&
      global_ba_trust_region != BundleAdjustmentOptions::TrustRegion::kLevenbergMarquardt)
    FailOption("--global-ba-trust-region", "dogleg or lm",
               static_cast<int>(global_ba_trust_region));
  // One observation does not fix a point: 0 (all) or at least 2.
  if (growth_ba_max_point_observations != 0 && growth_ba_max_point_observations < 2)
    FailOption("--growth-ba-max-track", "0 (all) or at least 2", growth_ba_max_point_observations);
  CheckNonNegative("--growth-ba-subset-images", growth_ba_subset_min_images);
  CheckNonNegative("--global-ba-iterative-images", global_ba_iterative_min_images);
  CheckPositive("--global-ba-cg-tolerance", global_ba_cg_tolerance);
  CheckAtLeast("--global-ba-cg-iterations", global_ba_cg_max_iterations, 1);
  CheckAtLeast("global_ba_max_iterations", global_ba_max_iterations, 1);
  CheckNonNegative("--degenerate-init-global-ba", degenerate_init_global_ba_images);
  CheckAtLeast("final_global_ba_max_iterations", final_global_ba_max_iterations, 1);
  CheckPositive("filter_max_error_px", filter_max_error_px);
  CheckInRange("filter_min_triangulation_angle_deg", filter_min_triangulation_angle_deg, 0, 180);
  CheckFraction("readjust_min_new_points_fraction", readjust_min_new_points_fraction);
}

ScheduledAdjustment BundleAdjustmentSchedule::Next(size_t n, size_t num_images,
                                                   bool degenerate_init) {
  // M0 <= 0: a global BA after every image (the Pollefeys-like baseline of the paper).
  const bool paper_global =
      options_.first_global_ba_images <= 0 ||
      (!first_global_done_ && n >= static_cast<size_t>(options_.first_global_ba_images));
  // A growth adjustment is skipped when the final one follows within half a growth step (all
  // images registered before the model grows by the factor's square root): it would redo nearly
  // the same problem (e.g. at 192 of 200 images). Not within a whole step: on a 1000-image
  // sequence that skipped the one due at 808 images, and the final one had to fix the drift of
  // ~420 images with local adjustments only.
  const bool final_within_growth =
      options_.final_global_ba &&
      num_images < std::sqrt(options_.global_ba_growth) * static_cast<double>(n);
  const bool growth_global = first_global_done_ && options_.global_ba_growth > 1.0 &&
                             n >= options_.global_ba_growth * last_global_size_ &&
                             !final_within_growth;
  if (paper_global || growth_global) {
    first_global_done_ = true;
    last_global_size_ = n;
    return paper_global ? ScheduledAdjustment::kGlobal : ScheduledAdjustment::kGrowth;
  }
  // Outside the schedule: M0 and the growth stay as they are.
  if (degenerate_init && options_.degenerate_init_global_ba_images > 0 &&
      n == static_cast<size_t>(options_.degenerate_init_global_ba_images))
    return ScheduledAdjustment::kSettleFocals;
  return ScheduledAdjustment::kLocal;
}

}  // namespace varsfm
