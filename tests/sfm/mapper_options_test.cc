// The mapper's options, part by part: each Check() passes its defaults and refuses a bad value
// with one line naming the option; the intrinsics policy's forms for the adjustments and the
// registration; the bundle-adjustment schedule's choices.
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/bad_option_values.h"
#include "varsfm/sfm/incremental_mapper.h"
#include "varsfm/util/option_check.h"

namespace varsfm {
namespace {

using testing::BadValue;
using testing::ExpectRejected;
using testing::kInf;
using testing::kNan;

// Each bad value, applied alone to the defaults, makes Check() throw OptionError naming its
// option, and so does the whole mapper's Check() for the part it holds.
template <typename Options>
void ExpectEachRejected(const std::vector<BadValue<Options>>& bad_values,
                        std::function<Options&(IncrementalMapperOptions&)> part) {
  ASSERT_NO_THROW(Options().Check());
  ASSERT_NO_THROW(IncrementalMapperOptions().Check());
  for (const BadValue<Options>& bad : bad_values) {
    Options options;
    bad.spoil(options);
    IncrementalMapperOptions mapper;
    bad.spoil(part(mapper));
    for (const std::function<void()>& check : {std::function<void()>([&] { options.Check(); }),
                                               std::function<void()>([&] { mapper.Check(); })}) {
      ExpectRejected(check, bad.option);
    }
  }
}

TEST(MapperOptions, RegistrationRefusesBadValues) {
  using O = ImageRegistrationOptions;
  ExpectEachRejected<O>(
      {{"--min-correspondences", [](O& o) { o.min_correspondences = 5; }},
       {"min_registration_inliers", [](O& o) { o.min_inliers = 2; }},
       {"registration.min_inlier_ratio", [](O& o) { o.min_inlier_ratio = 1.5; }},
       {"registration.relaxed_min_inliers", [](O& o) { o.relaxed_min_inliers = 5; }},
       {"registration.relaxed_min_inliers", [](O& o) { o.relaxed_min_inliers = 16; }},
       {"registration.relaxed_min_inlier_ratio", [](O& o) { o.relaxed_min_inlier_ratio = kNan; }},
       {"registration_max_error_px", [](O& o) { o.max_error_px = kNan; }},
       {"registration_max_error_px", [](O& o) { o.max_error_px = 0; }},
       {"registration.refinement_gate_factor", [](O& o) { o.refinement_gate_factor = 0.5; }},
       {"registration.pnp_max_iterations", [](O& o) { o.pnp_max_iterations = 0; }},
       {"registration.pnp_confidence", [](O& o) { o.pnp_confidence = 1.5; }},
       {"registration.min_focal_factor", [](O& o) { o.min_focal_factor = -1; }},
       {"registration.max_focal_factor", [](O& o) { o.max_focal_factor = 0.1; }},
       {"registration.max_focal_factor", [](O& o) { o.max_focal_factor = kInf; }},
       {"registration.dlt_min_focal_factor", [](O& o) { o.dlt_min_focal_factor = 0; }},
       {"registration.dlt_max_focal_factor", [](O& o) { o.dlt_max_focal_factor = 0.2; }},
       {"registration.dlt_min_aspect", [](O& o) { o.dlt_min_aspect = kNan; }},
       {"registration.dlt_max_aspect", [](O& o) { o.dlt_max_aspect = 0.5; }},
       {"registration.dlt_max_skew_fraction", [](O& o) { o.dlt_max_skew_fraction = 0; }},
       {"registration.dlt_max_principal_point_offset",
        [](O& o) { o.dlt_max_principal_point_offset = -0.3; }},
       {"registration.free_principal_point_max_cost_ratio",
        [](O& o) { o.free_principal_point_max_cost_ratio = 1.5; }},
       {"registration.free_principal_point_min_offset",
        [](O& o) { o.free_principal_point_min_offset = -0.1; }}},
      [](IncrementalMapperOptions& m) -> O& { return m.registration; });
}

TEST(MapperOptions, TriangulationRefusesBadValues) {
  using O = TrackTriangulationOptions;
  ExpectEachRejected<O>({{"triangulation_max_error_px", [](O& o) { o.max_error_px = -1; }},
                         {"min_triangulation_angle_deg", [](O& o) { o.min_angle_deg = 190; }},
                         {"min_triangulation_angle_deg", [](O& o) { o.min_angle_deg = kNan; }}},
                        [](IncrementalMapperOptions& m) -> O& { return m.triangulation; });
}

TEST(MapperOptions, ScheduleRefusesBadValues) {
  using O = BundleAdjustmentScheduleOptions;
  ExpectEachRejected<O>(
      {{"--local-ba-images", [](O& o) { o.local_ba_images = 0; }},
       {"--local-ba-max-track", [](O& o) { o.local_ba_max_track_length = -1; }},
       {"local_ba_max_iterations", [](O& o) { o.local_ba_max_iterations = 0; }},
       {"local_ba_function_tolerance", [](O& o) { o.local_ba_function_tolerance = kNan; }},
       {"--global-ba-images", [](O& o) { o.first_global_ba_images = -1; }},
       {"--global-ba-growth", [](O& o) { o.global_ba_growth = 1.0; }},
       {"--global-ba-growth", [](O& o) { o.global_ba_growth = kInf; }},
       {"--global-ba-tolerance", [](O& o) { o.global_ba_function_tolerance = 0; }},
       {"--growth-ba-tolerance", [](O& o) { o.growth_ba_function_tolerance = -1e-4; }},
       {"--two-view-filter", [](O& o) { o.final_two_view_filter_factor = -1; }},
       {"--two-view-filter", [](O& o) { o.final_two_view_filter_factor = kNan; }},
       {"--global-ba-trust-region",
        [](O& o) {
          o.global_ba_trust_region = static_cast<BundleAdjustmentOptions::TrustRegion>(9);
        }},
       {"--growth-ba-max-track", [](O& o) { o.growth_ba_max_point_observations = 1; }},
       {"--growth-ba-subset-images", [](O& o) { o.growth_ba_subset_min_images = -1; }},
       {"--global-ba-iterative-images", [](O& o) { o.global_ba_iterative_min_images = -1; }},
       {"--global-ba-cg-tolerance", [](O& o) { o.global_ba_cg_tolerance = 0; }},
       {"--global-ba-cg-iterations", [](O& o) { o.global_ba_cg_max_iterations = 0; }},
       {"global_ba_max_iterations", [](O& o) { o.global_ba_max_iterations = 0; }},
       {"--degenerate-init-global-ba", [](O& o) { o.degenerate_init_global_ba_images = -1; }},
       {"final_global_ba_max_iterations", [](O& o) { o.final_global_ba_max_iterations = -5; }},
       {"filter_max_error_px", [](O& o) { o.filter_max_error_px = 0; }},
       {"filter_min_triangulation_angle_deg",
        [](O& o) { o.filter_min_triangulation_angle_deg = -1; }},
       {"readjust_min_new_points_fraction", [](O& o) { o.readjust_min_new_points_fraction = 2; }}},
      [](IncrementalMapperOptions& m) -> O& { return m.adjustment; });
}

TEST(MapperOptions, IntrinsicsPolicyRefusesBadValues) {
  using O = IntrinsicsPolicy;
  ExpectEachRejected<O>(
      {{"--intrinsics", [](O& o) { o.sharing = static_cast<IntrinsicsSharing>(7); }},
       {"--zoom-band", [](O& o) { o.zoom_band_focal_ratio = 1.0; }},
       {"--zoom-band", [](O& o) { o.zoom_band_focal_ratio = -2; }},
       {"--zoom-band", [](O& o) { o.zoom_band_focal_ratio = kNan; }}},
      [](IncrementalMapperOptions& m) -> O& { return m.intrinsics; });
}

TEST(MapperOptions, InitialisationRefusesBadValues) {
  using O = IncrementalMapperOptions;
  ExpectEachRejected<O>(
      {{"max_initial_pair_trials", [](O& o) { o.max_initial_pair_trials = 0; }},
       {"min_initial_points", [](O& o) { o.min_initial_points = 0; }},
       {"init_min_median_angle_deg", [](O& o) { o.init_min_median_angle_deg = kInf; }},
       {"init_max_error_px", [](O& o) { o.init_max_error_px = 0; }},
       {"degenerate_focal_log_step", [](O& o) { o.degenerate_focal_log_step = kNan; }},
       {"degenerate_focal_max_steps", [](O& o) { o.degenerate_focal_max_steps = 0; }},
       {"min_num_matches", [](O& o) { o.initial_pair.min_num_matches = 0; }},
       {"--threads", [](O& o) { o.num_threads = -1; }}},
      [](IncrementalMapperOptions& m) -> O& { return m; });
}

// The default policy: focal length and k1, k2 per image, one principal point per image size
// estimated only where the whole model is adjusted; a new image refines its focal length alone.
TEST(IntrinsicsPolicy, DefaultSharesThePrincipalPointPerImageSize) {
  const IntrinsicsPolicy policy;
  const std::vector<int> pp = {Camera::kU0, Camera::kV0};
  EXPECT_EQ(policy.SharedPerSize(), pp);
  const IntrinsicsOptions global = policy.ForAdjustment(/*whole_model=*/true);
  EXPECT_TRUE(global.refine_focal && global.refine_principal_point && global.refine_k1 &&
              global.refine_k2);
  EXPECT_FALSE(global.refine_aspect || global.refine_skew);
  EXPECT_EQ(global.shared_per_size, pp);
  const IntrinsicsOptions local = policy.ForAdjustment(/*whole_model=*/false);
  EXPECT_TRUE(local.refine_focal && local.refine_k1 && local.refine_k2);
  EXPECT_FALSE(local.refine_principal_point);
  const IntrinsicsOptions new_camera = policy.ForRegistration(/*camera_registered=*/false);
  EXPECT_TRUE(new_camera.refine_focal);
  EXPECT_FALSE(new_camera.refine_principal_point || new_camera.refine_k1 || new_camera.refine_k2);
  EXPECT_EQ(HeldIntrinsics(policy.ForRegistration(/*camera_registered=*/true)).size(),
            static_cast<size_t>(Camera::kNumParams));
}

TEST(IntrinsicsPolicy, FocalPerImageSharesTheRestPerImageSize) {
  IntrinsicsPolicy policy;
  policy.sharing = IntrinsicsSharing::kFocalPerImage;
  const std::vector<int> rest = {Camera::kAspect, Camera::kSkew, Camera::kU0,
                                 Camera::kV0,     Camera::kK1,   Camera::kK2};
  EXPECT_EQ(policy.SharedPerSize(), rest);
  const IntrinsicsOptions local = policy.ForAdjustment(/*whole_model=*/false);
  EXPECT_TRUE(local.refine_focal);
  EXPECT_FALSE(local.refine_k1 || local.refine_k2 || local.refine_principal_point);
  const IntrinsicsOptions global = policy.ForAdjustment(/*whole_model=*/true);
  EXPECT_TRUE(global.refine_k1 && global.refine_k2 && global.refine_principal_point);
  // Refined per image, the principal point is in no group.
  policy.sharing = IntrinsicsSharing::kPerImage;
  policy.refine_principal_point = true;
  EXPECT_TRUE(policy.SharedPerSize().empty());
  EXPECT_TRUE(policy.ForAdjustment(/*whole_model=*/false).refine_principal_point);
}

// M0 = 13 of 100 images, growth x1.4: local adjustments, the global one at 13, growth ones at
// 19 and 27 (x1.4 of the last), none once the final one follows within half a growth step.
TEST(BundleAdjustmentSchedule, GlobalAtM0ThenAtEachGrowth) {
  const BundleAdjustmentScheduleOptions options;
  BundleAdjustmentSchedule schedule(options);
  std::vector<size_t> global, growth;
  for (size_t n = 3; n <= 100; ++n) {
    const ScheduledAdjustment next = schedule.Next(n, 100, /*degenerate_init=*/false);
    if (next == ScheduledAdjustment::kGlobal) global.push_back(n);
    if (next == ScheduledAdjustment::kGrowth) growth.push_back(n);
    EXPECT_NE(next, ScheduledAdjustment::kSettleFocals);
  }
  EXPECT_EQ(global, std::vector<size_t>({13}));
  // 13 x 1.4 = 18.2 -> 19, 26.6 -> 27, 37.8 -> 38, 53.2 -> 54, 75.6 -> 76; at 76 the final
  // one follows within sqrt(1.4) (100 < 1.183 x 76 = 89.9 is false, so 76 runs).
  EXPECT_EQ(growth, std::vector<size_t>({19, 27, 38, 54, 76}));
}

TEST(BundleAdjustmentSchedule, EveryImageWithM0ZeroAndSettleAfterADegeneratePair) {
  BundleAdjustmentScheduleOptions every;
  every.first_global_ba_images = 0;
  BundleAdjustmentSchedule after_each(every);
  for (size_t n = 3; n <= 10; ++n)
    EXPECT_EQ(after_each.Next(n, 10, false), ScheduledAdjustment::kGlobal) << n;

  const BundleAdjustmentScheduleOptions options;
  BundleAdjustmentSchedule schedule(options);
  EXPECT_EQ(schedule.Next(3, 20, /*degenerate_init=*/true), ScheduledAdjustment::kLocal);
  EXPECT_EQ(schedule.Next(4, 20, /*degenerate_init=*/true), ScheduledAdjustment::kSettleFocals);
  EXPECT_EQ(schedule.Next(5, 20, /*degenerate_init=*/true), ScheduledAdjustment::kLocal);
}

}  // namespace
}  // namespace varsfm
