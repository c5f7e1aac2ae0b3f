#include "varsfm/sfm/incremental_mapper.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <set>

#include "sfm/mapper_input.h"
#include "varsfm/eval/alignment.h"
#include "varsfm/synthetic/synthetic_scene.h"

namespace varsfm {
namespace {

using testing::MakeInput;
using testing::MapperInput;

SyntheticOptions ZoomingOrbit() {
  SyntheticOptions o;
  o.num_images = 12;
  o.num_points = 1500;
  o.focal_start = 800;
  o.focal_end = 1280;  // x1.6 zoom over the sequence
  o.k1 = -0.05;
  o.noise_sigma = 0.5;
  o.arc_degrees = 80;
  o.look_at_jitter = 0.6;
  return o;
}

// Each image's camera-centre error after the similarity that best aligns the model's centres to
// the scene's (image i + 1 is the scene's image i; all registered). Empty when no alignment.
std::vector<double> CentreErrors(const Reconstruction& rec, const SyntheticScene& scene) {
  std::vector<Eigen::Vector3d> estimated, truth;
  for (int i = 0; i < scene.NumImages(); ++i) {
    estimated.push_back(rec.image(i + 1).Center());
    truth.push_back(scene.poses[i].Center());
  }
  const AlignmentResult alignment = AlignSimilarity(estimated, truth);
  std::vector<double> errors;
  if (!alignment.success) return errors;
  for (size_t i = 0; i < estimated.size(); ++i)
    errors.push_back((alignment.sim * estimated[i] - truth[i]).norm());
  return errors;
}

// Maps the scene of `in` with `options`.
MapperSummary Reconstruct(MapperInput* in, const IncrementalMapperOptions& options = {}) {
  return IncrementalMapper(in->graph, {}, options).Reconstruct(&in->reconstruction);
}

// Moves image i's observations by `to_pixel` (a pixel of the scene's image -> the same point's
// pixel in the changed one: a crop, a zoom, another principal point), keeping those that land
// inside its camera's (changed) image.
void MapObservations(SyntheticScene* scene, int i,
                     const std::function<Eigen::Vector2d(const Eigen::Vector2d&)>& to_pixel) {
  const Camera& camera = scene->cameras[i];
  std::vector<SyntheticObservation> inside;
  for (SyntheticObservation obs : scene->observations[i]) {
    obs.pixel = to_pixel(obs.pixel);
    obs.true_pixel = to_pixel(obs.true_pixel);
    if (obs.true_pixel.x() >= 0 && obs.true_pixel.y() >= 0 && obs.true_pixel.x() < camera.width &&
        obs.true_pixel.y() < camera.height)
      inside.push_back(obs);
  }
  scene->observations[i] = std::move(inside);
}

// With either trust region for the global adjustments (the dogleg by default).
class ZoomingOrbitMapping : public ::testing::TestWithParam<BundleAdjustmentOptions::TrustRegion> {
};

TEST_P(ZoomingOrbitMapping, ReconstructsAtTheNoiseFloor) {
  const SyntheticScene scene = GenerateSyntheticScene(ZoomingOrbit());
  MapperInput in = MakeInput(scene);
  IncrementalMapperOptions options;
  options.adjustment.global_ba_trust_region = GetParam();
  IncrementalMapper mapper(in.graph, {}, options);
  const MapperSummary summary = mapper.Reconstruct(&in.reconstruction);
  ASSERT_TRUE(summary.success) << summary.message;
  const Reconstruction& rec = in.reconstruction;
  EXPECT_EQ(rec.NumRegisteredImages(), 12u);
  EXPECT_GT(rec.points3D().size(), 1000u);
  // 0.5 px per axis is 0.71 px per observation: the RMS must sit at (just under) that floor.
  EXPECT_LT(rec.RmsReprojectionError(), 0.75);

  // Focal lengths per image within 1 %, and camera centres after a similarity alignment.
  std::vector<Eigen::Vector3d> estimated, truth;
  for (int i = 0; i < scene.NumImages(); ++i) {
    const Image& image = rec.image(i + 1);
    ASSERT_TRUE(image.registered);
    const double f = rec.camera(image.camera_id).focal();
    EXPECT_NEAR(f / scene.cameras[i].focal(), 1.0, 0.01) << "image " << i;
    // k1 and k2 trade off per image; the distortion they describe must be the true one.
    const Camera& camera = rec.camera(image.camera_id);
    for (const double r : {0.2, 0.4}) {
      const double d =
          1 + camera.params[Camera::kK1] * r * r + camera.params[Camera::kK2] * std::pow(r, 4);
      EXPECT_NEAR(d, 1 - 0.05 * r * r, 0.004) << "image " << i << " r " << r;
    }
    estimated.push_back(image.Center());
    truth.push_back(scene.poses[i].Center());
  }
  const AlignmentResult alignment = AlignSimilarity(estimated, truth);
  ASSERT_TRUE(alignment.success);
  for (int i = 0; i < scene.NumImages(); ++i)
    EXPECT_LT((alignment.sim * estimated[i] - truth[i]).norm(), 0.01 * ZoomingOrbit().orbit_radius)
        << "image " << i;
}

INSTANTIATE_TEST_SUITE_P(
    IncrementalMapper, ZoomingOrbitMapping,
    ::testing::Values(BundleAdjustmentOptions::TrustRegion::kDogleg,
                      BundleAdjustmentOptions::TrustRegion::kLevenbergMarquardt),
    [](const auto& info) {
      return info.param == BundleAdjustmentOptions::TrustRegion::kDogleg
                 ? std::string("Dogleg")
                 : std::string("LevenbergMarquardt");
    });

// A longer sequence filmed sideways in order, so that the model grows past M0 and the growth
// adjustments run (13 images, then x1.4).
SyntheticOptions SidewaysFacade() {
  SyntheticOptions o;
  o.structure = SyntheticOptions::Structure::kFacade;
  o.path = SyntheticOptions::Path::kSideways;
  o.num_images = 36;
  o.num_points = 2500;
  o.scene_extent = 3.0;
  o.focal_start = 900;
  o.focal_end = 1300;
  o.noise_sigma = 0.5;
  return o;
}

// Maps `scene` in sequential order with `options` into `out`.
MapperSummary MapInOrder(const SyntheticScene& scene, IncrementalMapperOptions options,
                         Reconstruction* out) {
  MapperInput in = MakeInput(scene);
  options.sequential_order = true;
  const MapperSummary summary = Reconstruct(&in, options);
  *out = in.reconstruction;
  return summary;
}

// Every image registered, the RMS at the noise floor (0.5 px per axis: 0.71 px per observation),
// focal lengths within 1 % and centres within 1 % of the sequence's length.
void ExpectAtTheNoiseFloor(const Reconstruction& rec, const SyntheticScene& scene) {
  EXPECT_EQ(rec.NumRegisteredImages(), static_cast<size_t>(scene.NumImages()));
  EXPECT_LT(rec.RmsReprojectionError(), 0.75);
  for (int i = 0; i < scene.NumImages(); ++i) {
    const Image& image = rec.image(i + 1);
    if (!image.registered) continue;
    EXPECT_NEAR(rec.camera(image.camera_id).focal() / scene.cameras[i].focal(), 1.0, 0.01)
        << "image " << i;
  }
  const std::vector<double> errors = CentreErrors(rec, scene);
  ASSERT_EQ(errors.size(), static_cast<size_t>(scene.NumImages()));
  const double extent = (scene.poses.front().Center() - scene.poses.back().Center()).norm();
  for (size_t i = 0; i < errors.size(); ++i) EXPECT_LT(errors[i], 0.01 * extent) << "image " << i;
}

// With their looser tolerance the growth adjustments take fewer steps than at the final one's,
// and the final adjustment still brings the model to the noise floor.
TEST(IncrementalMapper, GrowthAdjustmentsStopEarlierAndTheModelReachesTheNoiseFloor) {
  const SyntheticScene scene = GenerateSyntheticScene(SidewaysFacade());
  const auto map = [&](double growth_tolerance, Reconstruction* out) {
    IncrementalMapperOptions options;
    options.adjustment.growth_ba_function_tolerance = growth_tolerance;
    return MapInOrder(scene, options, out);
  };
  Reconstruction loose, tight;
  const MapperSummary loose_summary = map(1e-4, &loose);
  const MapperSummary tight_summary = map(1e-8, &tight);
  ASSERT_TRUE(loose_summary.success) << loose_summary.message;
  ASSERT_TRUE(tight_summary.success) << tight_summary.message;
  // M0, at least two growth adjustments (13 -> 19 -> 27) and the final one.
  EXPECT_GE(loose_summary.num_global_ba, 4u);
  EXPECT_EQ(loose_summary.num_global_ba, tight_summary.num_global_ba);
  EXPECT_LT(loose_summary.num_global_ba_iterations, tight_summary.num_global_ba_iterations);
  ExpectAtTheNoiseFloor(loose, scene);
  ExpectAtTheNoiseFloor(tight, scene);
}

// The growth adjustments on track subsets (BundleAdjustmentScheduleOptions::
// growth_ba_max_point_observations, here from M0 on and 3 observations a point): the final,
// complete adjustment brings the model to the noise floor, near the model of complete growth
// adjustments.
TEST(IncrementalMapper, GrowthAdjustmentsOnTrackSubsetsLeaveTheFinalModelAtTheNoiseFloor) {
  const SyntheticScene scene = GenerateSyntheticScene(SidewaysFacade());
  const auto map = [&](int max_point_observations, Reconstruction* out) {
    IncrementalMapperOptions options;
    options.adjustment.growth_ba_subset_min_images = 13;
    options.adjustment.growth_ba_max_point_observations = max_point_observations;
    return MapInOrder(scene, options, out);
  };
  Reconstruction subsets, complete;
  const MapperSummary subsets_summary = map(3, &subsets);
  const MapperSummary complete_summary = map(0, &complete);
  ASSERT_TRUE(subsets_summary.success) << subsets_summary.message;
  ASSERT_TRUE(complete_summary.success) << complete_summary.message;
  EXPECT_GE(subsets_summary.num_global_ba, 4u);  // growth adjustments ran on the subsets
  ExpectAtTheNoiseFloor(subsets, scene);
  ExpectAtTheNoiseFloor(complete, scene);
  // The subsets changed the growth adjustments (the cap took effect), not where the model ends:
  // aligned by a similarity, the two models' centres agree within 0.05 % of the sequence's length
  // (the bound against the truth is 1 %).
  std::vector<Eigen::Vector3d> a, b;
  for (int i = 0; i < scene.NumImages(); ++i) {
    a.push_back(subsets.image(i + 1).Center());
    b.push_back(complete.image(i + 1).Center());
  }
  EXPECT_NE(a, b);
  const AlignmentResult alignment = AlignSimilarity(a, b);
  ASSERT_TRUE(alignment.success);
  const double extent = (b.front() - b.back()).norm();
  for (size_t i = 0; i < a.size(); ++i)
    EXPECT_LT((alignment.sim * a[i] - b[i]).norm(), 0.0005 * extent) << "image " << i;
}

// Runs in one process give the same model bit for bit, although the reconstructions live at
// different heap addresses (which used to change Ceres' block order; see ba/bundle_adjuster.h),
// and whatever the number of bundle-adjustment threads (the native solver sums in a fixed order).
TEST(IncrementalMapper, SameSeedSameModelBitForBit) {
  const SyntheticScene scene = GenerateSyntheticScene(ZoomingOrbit());
  MapperInput a = MakeInput(scene);
  ASSERT_TRUE(IncrementalMapper(a.graph, {}, IncrementalMapperOptions{})
                  .Reconstruct(&a.reconstruction)
                  .success);
  for (const int threads : {0, 1, 3}) {
    SCOPED_TRACE(threads);
    MapperInput b = MakeInput(scene);
    IncrementalMapperOptions options;
    options.num_threads = threads;
    ASSERT_TRUE(IncrementalMapper(b.graph, {}, options).Reconstruct(&b.reconstruction).success);
    ASSERT_EQ(a.reconstruction.points3D().size(), b.reconstruction.points3D().size());
    for (const auto& [id, image] : a.reconstruction.images()) {
      const Image& other = b.reconstruction.image(id);
      EXPECT_EQ(image.cam_from_world.translation, other.cam_from_world.translation) << id;
      EXPECT_EQ(image.cam_from_world.rotation.coeffs(), other.cam_from_world.rotation.coeffs())
          << id;
      EXPECT_EQ(a.reconstruction.camera(image.camera_id).params,
                b.reconstruction.camera(other.camera_id).params)
          << id;
    }
    for (const auto& [id, point] : a.reconstruction.points3D())
      EXPECT_EQ(point.xyz, b.reconstruction.point3D(id).xyz) << id;
  }
}

// The last image keeps 14 of its points, one short of min_inliers: only the second try at the
// relaxed thresholds (ImageRegistrationOptions::Relaxed) registers it, and near its true place.
TEST(IncrementalMapper, AWeaklyLinkedImageJoinsAtTheRelaxedThresholds) {
  SyntheticOptions o = ZoomingOrbit();
  o.num_images = 8;
  SyntheticScene scene = GenerateSyntheticScene(o);
  std::vector<SyntheticObservation>& weak = scene.observations.back();
  std::vector<SyntheticObservation> kept;
  const size_t step = weak.size() / 14;
  for (size_t k = 0; k < 14; ++k) kept.push_back(weak[k * step]);
  weak = kept;
  const image_t weak_id = static_cast<image_t>(scene.NumImages());
  for (const int relaxed_min_inliers : {0, 10}) {
    SCOPED_TRACE(relaxed_min_inliers);
    MapperInput in = MakeInput(scene);
    IncrementalMapperOptions options;
    options.registration.relaxed_min_inliers = relaxed_min_inliers;
    const MapperSummary summary = Reconstruct(&in, options);
    ASSERT_TRUE(summary.success) << summary.message;
    const Reconstruction& rec = in.reconstruction;
    EXPECT_EQ(rec.NumRegisteredImages(),
              static_cast<size_t>(scene.NumImages()) - (relaxed_min_inliers == 0 ? 1 : 0));
    EXPECT_EQ(summary.num_relaxed_registrations, relaxed_min_inliers == 0 ? 0u : 1u);
    if (relaxed_min_inliers == 0) continue;
    ASSERT_TRUE(rec.image(weak_id).registered);
    const std::vector<double> errors = CentreErrors(rec, scene);
    ASSERT_EQ(errors.size(), static_cast<size_t>(scene.NumImages()));
    EXPECT_LT(errors.back(), 0.02 * o.orbit_radius);
  }
}

// Every optical axis through (nearly) one point, as in entry-P10: the initial pair is degenerate
// for self-calibration and its focal lengths start from the prior, here 1.54x the true 800 px.
// A third view chooses the pair's focal length (SelectDegenerateFocal); the model grown from it
// reaches the true focal lengths.
TEST(IncrementalMapper, DegenerateInitialPairTakesItsFocalFromAThirdView) {
  SyntheticOptions o = ZoomingOrbit();
  o.focal_start = o.focal_end = 800;
  o.look_at_jitter = 0.05;
  o.arc_degrees = 60;
  const SyntheticScene scene = GenerateSyntheticScene(o);
  MapperInput in = MakeInput(scene);
  const MapperSummary summary = Reconstruct(&in);
  ASSERT_TRUE(summary.success) << summary.message;
  ASSERT_TRUE(summary.initial_focal_from_prior);
  const double truth_scale = 800 / (1.2 * std::max(o.width, o.height));
  EXPECT_NEAR(summary.initial_focal_scale / truth_scale, 1.0, 0.06);
  EXPECT_EQ(in.reconstruction.NumRegisteredImages(), 12u);
  for (const auto& [id, image] : in.reconstruction.images())
    EXPECT_NEAR(in.reconstruction.camera(image.camera_id).focal() / 800, 1.0, 0.01) << id;
}

// Photos of other sizes in one capture (another phone, a resized copy): two of the twelve are
// half-size. A new image starts from a registered neighbour's intrinsics, but not from its
// principal point when the sizes differ: two images of a size form no group (min_images_to_share
// is 3), so a borrowed principal point would stay, a quarter of the image off its centre.
TEST(IncrementalMapper, AnImageOfAnotherSizeKeepsItsOwnPrincipalPoint) {
  SyntheticOptions o = ZoomingOrbit();
  o.structure = SyntheticOptions::Structure::kFacade;
  SyntheticScene scene = GenerateSyntheticScene(o);
  const std::vector<int> half_size = {4, 9};
  for (const int i : half_size) {
    Camera& truth = scene.cameras[i];
    truth.width /= 2;
    truth.height /= 2;
    truth.focal() *= 0.5;
    truth.params[Camera::kU0] *= 0.5;
    truth.params[Camera::kV0] *= 0.5;
    for (auto& obs : scene.observations[i]) obs.pixel *= 0.5, obs.true_pixel *= 0.5;
  }
  MapperInput in = MakeInput(scene);
  const MapperSummary summary = Reconstruct(&in);
  ASSERT_TRUE(summary.success) << summary.message;
  const Reconstruction& rec = in.reconstruction;
  EXPECT_EQ(rec.NumRegisteredImages(), 12u);
  for (int i = 0; i < scene.NumImages(); ++i) {
    const Image& image = rec.image(i + 1);
    ASSERT_TRUE(image.registered) << "image " << i;
    const Camera& camera = rec.camera(image.camera_id);
    const Camera& truth = scene.cameras[i];
    EXPECT_NEAR(camera.params[Camera::kU0], truth.params[Camera::kU0], 0.02 * truth.width)
        << "image " << i;
    EXPECT_NEAR(camera.params[Camera::kV0], truth.params[Camera::kV0], 0.02 * truth.height)
        << "image " << i;
    EXPECT_NEAR(camera.focal() / truth.focal(), 1.0, 0.01) << "image " << i;
  }
  EXPECT_LT(rec.RmsReprojectionError(), 0.75);
}

// Photos cropped off-centre (a corner cut out in an editor): three of the twelve keep the
// bottom-right 55 % of their frame, so their principal point lies half their larger side from
// their centre, near their top-left corner. The first of that size cannot start from a centred
// principal point: its pose would fit with a wrong focal length and rotation, and pull the whole
// model (without the free principal point: the crops' principal points 0.4 of their width off,
// focal lengths 41 % off, the other cameras' centres up to 10 % of the orbit radius). The other
// two start from the first's principal point.
TEST(IncrementalMapper, PhotosCroppedOffCentreFindTheirPrincipalPoint) {
  SyntheticOptions o = ZoomingOrbit();
  o.structure = SyntheticOptions::Structure::kFacade;
  SyntheticScene scene = GenerateSyntheticScene(o);
  const std::set<int> cropped = {3, 7, 10};
  for (const int i : cropped) {
    Camera& truth = scene.cameras[i];
    const Eigen::Vector2d origin(0.45 * truth.width, 0.45 * truth.height);
    truth.width -= static_cast<int>(origin.x());
    truth.height -= static_cast<int>(origin.y());
    truth.params[Camera::kU0] -= origin.x();
    truth.params[Camera::kV0] -= origin.y();
    MapObservations(&scene, i,
                    [&](const Eigen::Vector2d& x) -> Eigen::Vector2d { return x - origin; });
  }
  MapperInput in = MakeInput(scene);
  const MapperSummary summary = Reconstruct(&in);
  ASSERT_TRUE(summary.success) << summary.message;
  const Reconstruction& rec = in.reconstruction;
  ASSERT_EQ(rec.NumRegisteredImages(), 12u);
  const std::vector<double> centre_errors = CentreErrors(rec, scene);
  ASSERT_EQ(centre_errors.size(), 12u);
  for (int i = 0; i < scene.NumImages(); ++i) {
    const Camera& camera = rec.camera(rec.image(i + 1).camera_id);
    const Camera& truth = scene.cameras[i];
    // A crop sees a narrower field with fewer points: its intrinsics and pose are looser
    // (measured: principal point 24 px = 4 % of its width off, focal length 4.6 %, centre 4.7 %
    // of the radius).
    const bool crop = cropped.count(i) > 0;
    const Eigen::Vector2d pp_error(camera.params[Camera::kU0] - truth.params[Camera::kU0],
                                   camera.params[Camera::kV0] - truth.params[Camera::kV0]);
    EXPECT_LT(pp_error.norm(), (crop ? 0.06 : 0.01) * truth.width) << "image " << i;
    EXPECT_NEAR(camera.focal() / truth.focal(), 1.0, crop ? 0.08 : 0.01) << "image " << i;
    EXPECT_LT(centre_errors[i], (crop ? 0.08 : 0.02) * o.orbit_radius) << "image " << i;
  }
  EXPECT_LT(rec.RmsReprojectionError(), 0.75);
}

// One camera for every photo (`--intrinsics shared`, a fixed lens) whose principal point lies 20
// px right of and 12 px below the image centre. The camera's many views pin the point down in
// the global adjustments; held at the centre, the rotations would carry the offset.
TEST(IncrementalMapper, OneSharedCameraEstimatesItsPrincipalPoint) {
  SyntheticOptions o = ZoomingOrbit();
  o.focal_end = o.focal_start;  // a fixed lens
  SyntheticScene scene = GenerateSyntheticScene(o);
  const Eigen::Vector2d offset(20, 12);
  for (int i = 0; i < scene.NumImages(); ++i) {
    Camera& truth = scene.cameras[i];
    truth.params[Camera::kU0] += offset.x();
    truth.params[Camera::kV0] += offset.y();
    MapObservations(&scene, i,
                    [&](const Eigen::Vector2d& x) -> Eigen::Vector2d { return x + offset; });
  }
  MapperInput in = MakeInput(scene);
  for (int i = 0; i < scene.NumImages(); ++i) in.reconstruction.image(i + 1).camera_id = 1;
  IncrementalMapperOptions options;
  options.intrinsics.sharing = IntrinsicsSharing::kShared;
  const MapperSummary summary = Reconstruct(&in, options);
  ASSERT_TRUE(summary.success) << summary.message;
  const Reconstruction& rec = in.reconstruction;
  ASSERT_EQ(rec.NumRegisteredImages(), 12u);
  const Camera& camera = rec.camera(1);
  const Camera& truth = scene.cameras[0];
  EXPECT_NEAR(camera.params[Camera::kU0], truth.params[Camera::kU0], 2.0);
  EXPECT_NEAR(camera.params[Camera::kV0], truth.params[Camera::kV0], 2.0);
  EXPECT_NEAR(camera.focal() / truth.focal(), 1.0, 0.005);
  const std::vector<double> errors = CentreErrors(rec, scene);
  ASSERT_EQ(errors.size(), 12u);
  for (int i = 0; i < 12; ++i) EXPECT_LT(errors[i], 0.01 * o.orbit_radius) << "image " << i;
}

// Two zoom settings of a digital zoom: the second half of the images is a centred crop
// magnified x1.6, so its focal length and its principal point's offset from the image centre are
// x1.6 the first half's. Each setting's principal point is found: one pooled over both (the
// images' size is one) is wrong for both, and the zoomed images' by more than 2 px.
TEST(IncrementalMapper, EachZoomSettingGetsItsOwnPrincipalPoint) {
  SyntheticOptions o = ZoomingOrbit();
  o.focal_end = o.focal_start;
  SyntheticScene scene = GenerateSyntheticScene(o);
  const Eigen::Vector2d offset(20, 12);  // at the first setting
  for (int i = 0; i < scene.NumImages(); ++i) {
    const double zoom = i < scene.NumImages() / 2 ? 1.0 : 1.6;
    Camera& truth = scene.cameras[i];
    const Eigen::Vector2d centre(truth.params[Camera::kU0], truth.params[Camera::kV0]);
    truth.focal() *= zoom;
    truth.params[Camera::kU0] += zoom * offset.x();
    truth.params[Camera::kV0] += zoom * offset.y();
    MapObservations(&scene, i, [&](const Eigen::Vector2d& x) -> Eigen::Vector2d {
      return centre + zoom * (x - centre + offset);
    });
  }
  MapperInput in = MakeInput(scene);
  const MapperSummary summary = Reconstruct(&in);
  ASSERT_TRUE(summary.success) << summary.message;
  const Reconstruction& rec = in.reconstruction;
  ASSERT_EQ(rec.NumRegisteredImages(), 12u);
  for (int i = 0; i < scene.NumImages(); ++i) {
    const Camera& camera = rec.camera(i + 1);
    const Camera& truth = scene.cameras[i];
    EXPECT_NEAR(camera.params[Camera::kU0], truth.params[Camera::kU0], 2.0) << "image " << i;
    EXPECT_NEAR(camera.params[Camera::kV0], truth.params[Camera::kV0], 2.0) << "image " << i;
    EXPECT_NEAR(camera.focal() / truth.focal(), 1.0, 0.01) << "image " << i;
  }
  const std::vector<double> errors = CentreErrors(rec, scene);
  ASSERT_EQ(errors.size(), 12u);
  for (int i = 0; i < 12; ++i) EXPECT_LT(errors[i], 0.01 * o.orbit_radius) << "image " << i;
}

TEST(IncrementalMapper, PureRotationCannotInitialise) {
  SyntheticOptions o = ZoomingOrbit();
  o.path = SyntheticOptions::Path::kPureRotation;
  o.num_images = 5;
  const SyntheticScene scene = GenerateSyntheticScene(o);
  MapperInput in = MakeInput(scene);
  IncrementalMapper mapper(in.graph, {}, IncrementalMapperOptions{});
  const MapperSummary summary = mapper.Reconstruct(&in.reconstruction);
  EXPECT_FALSE(summary.success);
  EXPECT_FALSE(summary.message.empty());
  EXPECT_EQ(in.reconstruction.NumRegisteredImages(), 0u);
}

}  // namespace
}  // namespace varsfm
