#include "varsfm/ba/bundle_adjuster.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <gtest/gtest.h>

#include "support/synthetic_reconstruction.h"
#include "varsfm/synthetic/synthetic_scene.h"

namespace varsfm {
namespace {

using testing::ReconstructionFromSynthetic;

// A 15-image orbit with a zoom sweep 800 -> 1280 px and 0.5 px noise (the brief's setting).
SyntheticOptions ZoomScene(uint64_t seed = 7) {
  SyntheticOptions o;
  o.num_images = 15;
  o.num_points = 1500;
  o.focal_start = 800.0;
  o.focal_end = 1280.0;
  o.noise_sigma = 0.5;
  o.seed = seed;
  return o;
}

// Moves every pose (~0.5 deg, ~2 % of the orbit radius), point (~2 % of the scene extent) and
// focal length (up to 5 %) off the truth, as an incremental mapper would hand them over.
void Perturb(Reconstruction* rec, uint64_t seed, const std::set<image_t>& only = {}) {
  Rng rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  for (const image_t id : rec->RegisteredImageIds()) {
    if (!only.empty() && !only.count(id)) continue;
    Rigid3d& pose = rec->image(id).cam_from_world;
    const Eigen::Vector3d axis(n(rng), n(rng), n(rng));
    pose.rotation = Eigen::AngleAxisd(0.5 * M_PI / 180.0, axis.normalized()) * pose.rotation;
    pose.translation += 0.1 * Eigen::Vector3d(n(rng), n(rng), n(rng));
    rec->CameraOf(id).focal() *= 1.0 + u(rng);
  }
  for (auto& [id, point] : rec->points3D())
    point.xyz += 0.02 * Eigen::Vector3d(n(rng), n(rng), n(rng));
}

// The expected RMS of the 2D reprojection error (the norm, as BundleAdjustmentSummary and
// Reconstruction report it) at the least-squares optimum with Gaussian noise sigma per
// coordinate: sigma * sqrt(2) * sqrt((m - p) / m), m scalar residuals, p free parameters (gauge
// removed).
double NoiseFloor(const Reconstruction& rec, int free_intrinsics_per_camera, double sigma) {
  const double m = 2.0 * rec.NumObservations();
  const double p = 3.0 * rec.points3D().size() + 6.0 * rec.NumRegisteredImages() - 7.0 +
                   free_intrinsics_per_camera * rec.cameras().size();
  return sigma * std::sqrt(2.0 * (m - p) / m);
}

double MaxFocalError(const Reconstruction& rec, const SyntheticScene& scene) {
  double worst = 0.0;
  for (int i = 0; i < scene.NumImages(); ++i)
    worst = std::max(worst, std::abs(rec.camera(i + 1).focal() / scene.cameras[i].focal() - 1.0));
  return worst;
}

bool SameBits(const double* a, const double* b, size_t n) {
  return std::memcmp(a, b, n * sizeof(double)) == 0;
}

TEST(BundleAdjuster, GlobalReachesNoiseFloorAndRecoversZoomFocals) {
  const SyntheticScene scene = GenerateSyntheticScene(ZoomScene());
  Reconstruction rec = ReconstructionFromSynthetic(scene);
  Perturb(&rec, 1);
  // Gauge (bundle_adjuster.h): the pose of the image nearest the centres' centroid is held, and
  // the largest coordinate of C - C0 of the image farthest from it.
  const std::vector<image_t> ids = rec.RegisteredImageIds();
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const image_t id : ids) centroid += rec.image(id).Center();
  centroid /= static_cast<double>(ids.size());
  image_t held = ids.front();
  for (const image_t id : ids)
    if ((rec.image(id).Center() - centroid).norm() < (rec.image(held).Center() - centroid).norm())
      held = id;
  const Eigen::Vector3d c0 = rec.image(held).Center();
  image_t far = ids.front();
  for (const image_t id : ids)
    if ((rec.image(id).Center() - c0).norm() > (rec.image(far).Center() - c0).norm()) far = id;
  int k = 0;
  (rec.image(far).Center() - c0).cwiseAbs().maxCoeff(&k);
  const double far_coordinate = rec.image(far).Center()[k];
  const Rigid3d held_pose = rec.image(held).cam_from_world;
  ASSERT_NE(held, ids.front());  // the scene's first image is not the one held

  const BundleAdjustmentSummary s =
      RunBundleAdjustment({}, BundleAdjustmentConfig::Global(rec), &rec);
  ASSERT_TRUE(s.success) << s.report;
  EXPECT_GT(s.initial_rms_px, 10.0);
  const double floor = NoiseFloor(rec, 3, 0.5);  // f, k1, k2 free
  EXPECT_NEAR(s.final_rms_px, floor, 0.1 * floor) << s.report;
  EXPECT_LT(MaxFocalError(rec, scene), 0.01);
  EXPECT_TRUE(SameBits(held_pose.rotation.coeffs().data(),
                       rec.image(held).cam_from_world.rotation.coeffs().data(), 4));
  EXPECT_TRUE(
      SameBits(held_pose.translation.data(), rec.image(held).cam_from_world.translation.data(), 3));
  EXPECT_NEAR(rec.image(far).Center()[k], far_coordinate, 1e-9);
}

// The largest radial displacement difference (px) between two distortion profiles of a camera,
// over the normalised radii its observations cover: k1 and k2 are correlated over a finite field
// of view, so the profile where there is data is what the data pin down (beyond it they
// extrapolate freely).
double DistortionProfileError(const Camera& estimate, const Camera& truth,
                              const std::vector<SyntheticObservation>& observations) {
  double r_max = 0.0;
  for (const auto& obs : observations)
    r_max = std::max(r_max, truth.ImageToNormalized(obs.true_pixel).norm());
  double worst = 0.0;
  for (int i = 1; i <= 50; ++i) {
    const double r = r_max * i / 50.0, r2 = r * r;
    const auto radial = [&](const Camera& c) {
      return c.params[Camera::kK1] * r2 + c.params[Camera::kK2] * r2 * r2;
    };
    worst = std::max(worst, truth.focal() * r * std::abs(radial(estimate) - radial(truth)));
  }
  return worst;
}

// Per-image k1 = -0.1, k2 = 0.02 started at 0: each image's distortion profile is recovered to
// a fraction of a pixel at the image corner, and a lens shared by all images to tight k1, k2.
TEST(BundleAdjuster, RecoversRadialDistortionFromZero) {
  SyntheticOptions o = ZoomScene(11);
  o.k1 = -0.1;
  o.k2 = 0.02;
  for (const bool shared : {false, true}) {
    if (shared) o.focal_start = o.focal_end = 1000.0;
    const SyntheticScene scene = GenerateSyntheticScene(o);
    Reconstruction rec = ReconstructionFromSynthetic(scene);
    if (shared)
      for (const image_t id : rec.RegisteredImageIds()) rec.image(id).camera_id = 1;
    Perturb(&rec, 2);
    for (const image_t id : rec.RegisteredImageIds()) {
      rec.CameraOf(id).params[Camera::kK1] = 0.0;
      rec.CameraOf(id).params[Camera::kK2] = 0.0;
    }
    const BundleAdjustmentSummary s =
        RunBundleAdjustment({}, BundleAdjustmentConfig::Global(rec), &rec);
    ASSERT_TRUE(s.success) << s.report;
    const double floor = NoiseFloor(rec, 3, 0.5);
    EXPECT_NEAR(s.final_rms_px, floor, 0.1 * floor);
    EXPECT_LT(MaxFocalError(rec, scene), 0.01);
    double worst_profile = 0.0;
    for (const image_t id : rec.RegisteredImageIds())
      worst_profile =
          std::max(worst_profile, DistortionProfileError(rec.CameraOf(id), scene.cameras[id - 1],
                                                         scene.observations[id - 1]));
    const Camera& c = rec.CameraOf(1);
    std::printf("shared %d: k1 %.4f k2 %.4f (camera 1), worst profile error %.3f px\n", shared,
                c.params[Camera::kK1], c.params[Camera::kK2], worst_profile);
    EXPECT_LT(worst_profile, shared ? 0.2 : 1.0);
    if (shared) {
      EXPECT_NEAR(c.params[Camera::kK1], -0.1, 0.005);
      EXPECT_NEAR(c.params[Camera::kK2], 0.02, 0.01);
    }
  }
}

TEST(BundleAdjuster, LocalLeavesConstantImagesBitForBitUntouched) {
  const SyntheticScene scene = GenerateSyntheticScene(ZoomScene(3));
  Reconstruction rec = ReconstructionFromSynthetic(scene);
  const std::vector<image_t> variable = {13, 14, 15};
  Perturb(&rec, 3, {variable.begin(), variable.end()});
  const BundleAdjustmentConfig config = BundleAdjustmentConfig::Local(rec, variable);
  EXPECT_GE(config.constant_pose_images.size(), 5u);
  EXPECT_EQ(config.constant_cameras.size(), config.constant_pose_images.size());
  const Reconstruction before = rec;
  const BundleAdjustmentSummary s = RunBundleAdjustment({}, config, &rec);
  ASSERT_TRUE(s.success) << s.report;
  EXPECT_LT(s.final_rms_px, 0.75);
  for (const image_t id : config.constant_pose_images) {
    const Rigid3d& a = before.image(id).cam_from_world;
    const Rigid3d& b = rec.image(id).cam_from_world;
    EXPECT_TRUE(SameBits(a.rotation.coeffs().data(), b.rotation.coeffs().data(), 4)) << id;
    EXPECT_TRUE(SameBits(a.translation.data(), b.translation.data(), 3)) << id;
    EXPECT_TRUE(SameBits(before.CameraOf(id).params.data(), rec.CameraOf(id).params.data(),
                         Camera::kNumParams))
        << id;
  }
  // The variable images were pulled back to the truth: the constant ones fix the gauge.
  for (const image_t id : variable) {
    EXPECT_LT((rec.image(id).Center() - scene.poses[id - 1].Center()).norm(), 0.01);
    EXPECT_NEAR(rec.CameraOf(id).focal(), scene.cameras[id - 1].focal(),
                0.01 * scene.cameras[id - 1].focal());
  }
}

// With a track-length cap, long-track points are held and enter only through the variable
// images' observations; they bring in no other image, and the poses still converge.
TEST(BundleAdjuster, LocalTrackCapHoldsLongTracks) {
  const SyntheticScene scene = GenerateSyntheticScene(ZoomScene(11));
  Reconstruction rec = ReconstructionFromSynthetic(scene);
  const std::vector<image_t> variable = {13, 14, 15};
  constexpr size_t kCap = 6;
  const BundleAdjustmentConfig full = BundleAdjustmentConfig::Local(rec, variable);
  const BundleAdjustmentConfig capped = BundleAdjustmentConfig::Local(rec, variable, kCap);
  EXPECT_TRUE(full.constant_points.empty());
  ASSERT_FALSE(capped.constant_points.empty());
  EXPECT_LT(capped.constant_pose_images.size(), full.constant_pose_images.size());
  size_t expected_residuals = 0;
  std::set<point3D_t> seen;
  for (const image_t id : variable)
    for (const Point2D& p : rec.image(id).points2D)
      if (p.HasPoint3D()) seen.insert(p.point3D_id);
  for (const point3D_t id : seen) {
    const auto& track = rec.point3D(id).track;
    EXPECT_EQ(capped.constant_points.count(id) > 0, track.size() > kCap) << id;
    size_t n = 0;
    for (const TrackElement& el : track)
      n += capped.variable_pose_images.count(el.image_id) ||
           (track.size() <= kCap && capped.constant_pose_images.count(el.image_id));
    if (track.size() > kCap || n >= 2) expected_residuals += n;
  }
  // Move the variable images off the truth (0.5 deg, 5 cm, 3 % focal length).
  for (const image_t id : variable) {
    Rigid3d& pose = rec.image(id).cam_from_world;
    pose.rotation = Eigen::AngleAxisd(0.5 * M_PI / 180.0, Eigen::Vector3d::UnitY()) * pose.rotation;
    pose.translation += Eigen::Vector3d(0.05, -0.03, 0.02);
    rec.CameraOf(id).focal() *= 1.03;
  }
  const Reconstruction before = rec;
  const BundleAdjustmentSummary s = RunBundleAdjustment({}, capped, &rec);
  ASSERT_TRUE(s.success) << s.report;
  EXPECT_EQ(static_cast<size_t>(s.num_residuals), expected_residuals);
  for (const point3D_t id : capped.constant_points)
    EXPECT_TRUE(SameBits(before.point3D(id).xyz.data(), rec.point3D(id).xyz.data(), 3)) << id;
  for (const image_t id : variable) {
    EXPECT_LT((rec.image(id).Center() - scene.poses[id - 1].Center()).norm(), 0.01);
    EXPECT_NEAR(rec.CameraOf(id).focal(), scene.cameras[id - 1].focal(),
                0.01 * scene.cameras[id - 1].focal());
  }
}

// A global adjustment on a subset of each long track (the growth adjustments of a densifying
// set): each point enters with min(track length, cap) residuals, and from a perturbed start the
// subset brings every image to where the complete adjustment does, within the noise (both fix
// the gauge the same way, from the same start: the centres compare directly).
TEST(BundleAdjuster, GlobalPointObservationCapKeepsEveryImageDetermined) {
  const SyntheticScene scene = GenerateSyntheticScene(ZoomScene(21));
  Reconstruction rec = ReconstructionFromSynthetic(scene);
  Perturb(&rec, 2);
  Reconstruction complete = rec;
  constexpr size_t kCap = 4;
  BundleAdjustmentConfig config = BundleAdjustmentConfig::Global(rec);
  config.max_point_observations = kCap;
  size_t expected_residuals = 0;
  size_t longer = 0;
  for (const auto& [id, point] : rec.points3D()) {
    if (point.track.size() >= 2) expected_residuals += std::min(point.track.size(), kCap);
    longer += point.track.size() > kCap;
  }
  ASSERT_GT(longer, rec.points3D().size() / 2);  // the cap drops observations of most points
  const BundleAdjustmentSummary s = RunBundleAdjustment({}, config, &rec);
  ASSERT_TRUE(s.success) << s.report;
  EXPECT_EQ(static_cast<size_t>(s.num_residuals), expected_residuals);
  EXPECT_LT(s.final_rms_px, 0.8) << s.report;  // noise 0.5 px per coordinate
  EXPECT_LT(MaxFocalError(rec, scene), 0.01);
  ASSERT_TRUE(RunBundleAdjustment({}, BundleAdjustmentConfig::Global(complete), &complete).success);
  // 1 % of the orbit radius (5, SyntheticOptions).
  for (const image_t id : rec.RegisteredImageIds()) {
    EXPECT_LT((rec.image(id).Center() - complete.image(id).Center()).norm(), 0.05) << id;
    EXPECT_NEAR(rec.CameraOf(id).focal(), complete.CameraOf(id).focal(),
                0.01 * complete.CameraOf(id).focal())
        << id;
  }
}

TEST(BundleAdjuster, HeldIntrinsicsStayExactly) {
  const SyntheticScene scene = GenerateSyntheticScene(ZoomScene(5));
  Reconstruction rec = ReconstructionFromSynthetic(scene);
  Perturb(&rec, 5);
  const Reconstruction before = rec;
  BundleAdjustmentOptions options;
  options.intrinsics.refine_k1 = options.intrinsics.refine_k2 = false;  // focal only
  ASSERT_TRUE(RunBundleAdjustment(options, BundleAdjustmentConfig::Global(rec), &rec).success);
  for (const auto& [id, camera] : rec.cameras()) {
    const Camera& old = before.camera(id);
    EXPECT_NE(camera.focal(), old.focal());
    for (int k = Camera::kAspect; k < Camera::kNumParams; ++k)
      EXPECT_TRUE(SameBits(&camera.params[k], &old.params[k], 1)) << "camera " << id << " " << k;
  }
  // Every intrinsic held: the camera blocks are constant.
  options.intrinsics = {false, false, false, false, false, false};
  Reconstruction rec2 = before;
  ASSERT_TRUE(RunBundleAdjustment(options, BundleAdjustmentConfig::Global(rec2), &rec2).success);
  for (const auto& [id, camera] : rec2.cameras())
    EXPECT_TRUE(SameBits(camera.params.data(), before.camera(id).params.data(), 7));
}

TEST(BundleAdjuster, SharedCameraIsOneParameterBlock) {
  SyntheticOptions o = ZoomScene(9);
  o.focal_start = o.focal_end = 1000.0;  // one fixed-focal camera for every image
  const SyntheticScene scene = GenerateSyntheticScene(o);
  Reconstruction rec = ReconstructionFromSynthetic(scene);
  for (const image_t id : rec.RegisteredImageIds()) rec.image(id).camera_id = 1;
  // Poses and points start at the truth (with the seed-9 perturbation of the other tests, 8
  // observations end in a local minimum at > 3 px, whatever the loss); the shared focal starts
  // 10 % off.
  rec.camera(1).focal() = 1100.0;
  const Reconstruction before = rec;
  const BundleAdjustmentSummary s =
      RunBundleAdjustment({}, BundleAdjustmentConfig::Global(rec), &rec);
  ASSERT_TRUE(s.success) << s.report;
  EXPECT_NEAR(rec.camera(1).focal(), 1000.0, 2.0);
  EXPECT_LT(s.final_rms_px, 1.1 * NoiseFloor(rec, 3, 0.5)) << s.report;
  for (camera_t id = 2; id <= 15; ++id)  // unused cameras are not in the problem
    EXPECT_TRUE(SameBits(rec.camera(id).params.data(), before.camera(id).params.data(), 7));
}

// Gross outliers (uniform random pixels) on 5 % of the observations: the robust losses keep the
// zoom focals within 1 % while the squared loss is dragged off.
class RobustLoss : public ::testing::TestWithParam<BundleAdjustmentOptions::Loss> {};

TEST_P(RobustLoss, FivePercentOutliers) {
  SyntheticOptions o = ZoomScene(13);
  o.outlier_ratio = 0.05;
  const SyntheticScene scene = GenerateSyntheticScene(o);
  Reconstruction rec = ReconstructionFromSynthetic(scene);
  Perturb(&rec, 13);
  BundleAdjustmentOptions options;
  options.loss = GetParam();
  const BundleAdjustmentSummary s =
      RunBundleAdjustment(options, BundleAdjustmentConfig::Global(rec), &rec);
  ASSERT_TRUE(s.success) << s.report;
  // RMS over the inlier observations only.
  double sum = 0;
  size_t n = 0;
  for (const auto& [pid, point] : rec.points3D())
    for (const TrackElement& el : point.track)
      if (!scene.observations[el.image_id - 1][el.point2D_idx].outlier) {
        sum += rec.SquaredReprojectionError(el, point.xyz);
        ++n;
      }
  const double inlier_rms = std::sqrt(sum / n);
  const double focal_error = MaxFocalError(rec, scene);
  std::printf("loss %d: inlier RMS %.3f px, max focal error %.3f %%\n",
              static_cast<int>(GetParam()), inlier_rms, 100 * focal_error);
  if (GetParam() == BundleAdjustmentOptions::Loss::kTrivial) {
    EXPECT_GT(inlier_rms, 1.0);  // the squared loss spreads the outliers over the inliers
  } else {
    EXPECT_LT(inlier_rms, 1.1 * NoiseFloor(rec, 3, 0.5));
    EXPECT_LT(focal_error, 0.01);
  }
}

INSTANTIATE_TEST_SUITE_P(Losses, RobustLoss,
                         ::testing::Values(BundleAdjustmentOptions::Loss::kTrivial,
                                           BundleAdjustmentOptions::Loss::kHuber,
                                           BundleAdjustmentOptions::Loss::kCauchy));

// All images of one physical camera share a principal point off the image centre (as
// fountain-P11's, 7.4 px off). Held at the centre it biases every rotation; shared, it is
// recovered from all views together, while each focal length stays per image.
TEST(BundleAdjuster, SharedPrincipalPointRecoversACommonOffset) {
  const SyntheticScene scene = GenerateSyntheticScene(ZoomScene(11));
  Reconstruction rec = ReconstructionFromSynthetic(scene);
  // A shift of (u0, v0) moves every projection by exactly that shift (camera.h).
  const Eigen::Vector2d offset(6.0, -4.0);
  for (const image_t id : rec.RegisteredImageIds())
    for (Point2D& p : rec.image(id).points2D) p.xy += offset;
  Perturb(&rec, 5);

  BundleAdjustmentOptions options;
  options.intrinsics.refine_principal_point = true;
  options.intrinsics.shared_per_size = {Camera::kU0, Camera::kV0};
  const BundleAdjustmentSummary s =
      RunBundleAdjustment(options, BundleAdjustmentConfig::Global(rec), &rec);
  ASSERT_TRUE(s.success) << s.report;
  const double floor = NoiseFloor(rec, 3, 0.5);
  EXPECT_NEAR(s.final_rms_px, floor, 0.1 * floor) << s.report;
  EXPECT_LT(MaxFocalError(rec, scene), 0.01);
  const Camera& first = rec.camera(1);
  for (int i = 0; i < scene.NumImages(); ++i) {
    const Camera& c = rec.camera(i + 1);
    const Eigen::Vector2d truth = Eigen::Vector2d(scene.cameras[i].params[Camera::kU0],
                                                  scene.cameras[i].params[Camera::kV0]) +
                                  offset;
    EXPECT_LT((Eigen::Vector2d(c.params[Camera::kU0], c.params[Camera::kV0]) - truth).norm(), 1.0)
        << "image " << i + 1;
    EXPECT_EQ(c.params[Camera::kU0], first.params[Camera::kU0]) << "one shared value";
    EXPECT_EQ(c.params[Camera::kV0], first.params[Camera::kV0]) << "one shared value";
  }
}

// A local adjustment never shares: the constant images' cameras keep their principal points,
// and fewer than min_images_to_share variable cameras hold theirs.
TEST(BundleAdjuster, SharedPrincipalPointNeedsEnoughImages) {
  const SyntheticScene scene = GenerateSyntheticScene(ZoomScene(12));
  Reconstruction rec = ReconstructionFromSynthetic(scene);
  Perturb(&rec, 6, {14, 15});
  BundleAdjustmentOptions options;
  options.intrinsics.refine_principal_point = true;
  options.intrinsics.shared_per_size = {Camera::kU0, Camera::kV0};
  const Camera before = rec.camera(15);
  ASSERT_TRUE(
      RunBundleAdjustment(options, BundleAdjustmentConfig::Local(rec, {14, 15}), &rec).success);
  EXPECT_EQ(rec.camera(15).params[Camera::kU0], before.params[Camera::kU0]);
  EXPECT_EQ(rec.camera(15).params[Camera::kV0], before.params[Camera::kV0]);
}

// "Focal length per image, the rest shared": a zooming camera whose lens keeps one distortion
// and principal point; each focal length is recovered, k1 and k2 as one shared value.
TEST(BundleAdjuster, FocalPerImageRestSharedRecoversZoomAndDistortion) {
  SyntheticOptions o = ZoomScene(13);
  o.k1 = -0.1;
  o.k2 = 0.02;
  const SyntheticScene scene = GenerateSyntheticScene(o);
  Reconstruction rec = ReconstructionFromSynthetic(scene);
  Perturb(&rec, 7);
  for (const image_t id : rec.RegisteredImageIds()) {
    rec.CameraOf(id).params[Camera::kK1] = 0.0;
    rec.CameraOf(id).params[Camera::kK2] = 0.0;
  }
  BundleAdjustmentOptions options;
  options.intrinsics.shared_per_size = {Camera::kAspect, Camera::kSkew, Camera::kU0,
                                        Camera::kV0,     Camera::kK1,   Camera::kK2};
  const BundleAdjustmentSummary s =
      RunBundleAdjustment(options, BundleAdjustmentConfig::Global(rec), &rec);
  ASSERT_TRUE(s.success) << s.report;
  // f per image, k1 and k2 once: fewer free parameters than the per-image floor assumes.
  const double floor = NoiseFloor(rec, 1, 0.5);
  EXPECT_NEAR(s.final_rms_px, floor, 0.1 * floor) << s.report;
  EXPECT_LT(MaxFocalError(rec, scene), 0.01);
  for (const image_t id : rec.RegisteredImageIds()) {
    const Camera& c = rec.CameraOf(id);
    EXPECT_EQ(c.params[Camera::kK1], rec.CameraOf(1).params[Camera::kK1]) << "one shared value";
    EXPECT_EQ(c.params[Camera::kK2], rec.CameraOf(1).params[Camera::kK2]) << "one shared value";
    EXPECT_EQ(c.params[Camera::kAspect], 1.0) << "held";
  }
  EXPECT_NEAR(rec.CameraOf(1).params[Camera::kK1], -0.1, 0.005);
  EXPECT_NEAR(rec.CameraOf(1).params[Camera::kK2], 0.02, 0.01);
}

// The project's Schur solver (ba/schur_solver.h, LM) and Ceres' DENSE_SCHUR solve the
// same model: from the same start they reach the same minimum, for a global adjustment with the
// mapper's shared principal point and robust loss, a local one with constant images and held
// long-track points, and a shared camera (pose blocks apart from the camera block).
class NativeSolver : public ::testing::TestWithParam<int> {};

TEST_P(NativeSolver, ReachesCeresMinimum) {
  const SyntheticScene scene = GenerateSyntheticScene(ZoomScene(21));
  Reconstruction start = ReconstructionFromSynthetic(scene);
  BundleAdjustmentConfig config = BundleAdjustmentConfig::Global(start);
  BundleAdjustmentOptions options;
  options.function_tolerance = 1e-10;  // both run to the minimum
  options.gradient_tolerance = 1e-10;
  options.parameter_tolerance = 1e-10;
  if (GetParam() == 0) {
    Perturb(&start, 21);
    options.intrinsics.refine_principal_point = true;
    options.intrinsics.shared_per_size = {Camera::kU0, Camera::kV0};
  } else if (GetParam() == 1) {
    const std::vector<image_t> variable = {7, 8, 9};
    Perturb(&start, 22, {variable.begin(), variable.end()});
    config = BundleAdjustmentConfig::Local(start, variable, 6);
    ASSERT_FALSE(config.constant_points.empty());
  } else {
    for (const image_t id : start.RegisteredImageIds()) start.image(id).camera_id = 1;
    start.camera(1).focal() *= 1.05;
    options.max_iterations = 25;  // both crawl on to 100 iterations along the same path
  }
  Reconstruction native = start, ceres = start;
  options.solver = BundleAdjustmentOptions::Solver::kNativeDenseSchur;
  const BundleAdjustmentSummary a = RunBundleAdjustment(options, config, &native);
  options.solver = BundleAdjustmentOptions::Solver::kDenseSchur;
  const BundleAdjustmentSummary b = RunBundleAdjustment(options, config, &ceres);
  ASSERT_TRUE(a.success) << a.report;
  ASSERT_TRUE(b.success) << b.report;
  EXPECT_EQ(a.solver, "NATIVE_DENSE_SCHUR");
  EXPECT_LT(a.final_rms_px, a.initial_rms_px);
  EXPECT_NEAR(a.final_rms_px, b.final_rms_px, 1e-6 * b.final_rms_px);
  std::printf("native %.3f s: %s\nCeres %.3f s: %s\n", a.seconds, a.report.c_str(), b.seconds,
              b.report.c_str());
  for (const image_t id : start.RegisteredImageIds()) {
    // Within the solvers' stopping slack: 1e-6 of a focal length, 1e-3 px, 1e-5 of the orbit
    // radius (5; the zoom-distance valley of a global adjustment is flat).
    EXPECT_NEAR(native.CameraOf(id).focal(), ceres.CameraOf(id).focal(),
                1e-6 * ceres.CameraOf(id).focal())
        << id;
    EXPECT_NEAR(native.CameraOf(id).params[Camera::kU0], ceres.CameraOf(id).params[Camera::kU0],
                1e-3)
        << id;
    EXPECT_LT((native.image(id).Center() - ceres.image(id).Center()).norm(), 5e-5) << id;
  }
  // Reproducible bit for bit.
  Reconstruction again = start;
  options.solver = BundleAdjustmentOptions::Solver::kNativeDenseSchur;
  RunBundleAdjustment(options, config, &again);
  for (const auto& [id, point] : native.points3D())
    ASSERT_TRUE(SameBits(point.xyz.data(), again.point3D(id).xyz.data(), 3)) << id;
}

std::string NativeSolverProblemName(const ::testing::TestParamInfo<int>& info) {
  static const char* const kNames[] = {"GlobalSharedPrincipalPoint", "LocalWithHeldPoints",
                                       "SharedCamera"};
  return kNames[info.param];
}
INSTANTIATE_TEST_SUITE_P(Problems, NativeSolver, ::testing::Values(0, 1, 2),
                         NativeSolverProblemName);

TEST(BundleAdjuster, EmptyConfigIsNotASuccess) {
  Reconstruction rec = ReconstructionFromSynthetic(GenerateSyntheticScene(ZoomScene()));
  EXPECT_FALSE(RunBundleAdjustment({}, BundleAdjustmentConfig{}, &rec).success);
}

}  // namespace
}  // namespace varsfm
