#include "varsfm/synthetic/synthetic_scene.h"

#include <cmath>
#include <numbers>
#include <unordered_map>

#include "varsfm/util/error.h"

namespace varsfm {
namespace {

Eigen::Vector3d RandomPoint(const SyntheticOptions& o, Rng& rng) {
  std::uniform_real_distribution<double> u(-o.scene_extent, o.scene_extent);
  switch (o.structure) {
    case SyntheticOptions::Structure::kPlane: return {u(rng), u(rng), 0.0};
    case SyntheticOptions::Structure::kFacade: return {u(rng), u(rng), 0.2 * u(rng)};
    case SyntheticOptions::Structure::kBox: break;
  }
  return {u(rng), u(rng), u(rng)};
}

// Camera centre and look-at target of image i along the path (world y points down).
Rigid3d PathPose(const SyntheticOptions& o, int i, Rng& rng) {
  const double t = o.num_images > 1 ? static_cast<double>(i) / (o.num_images - 1) : 0.5;
  const double arc = o.arc_degrees * std::numbers::pi / 180.0;
  std::uniform_real_distribution<double> jitter(-o.look_at_jitter, o.look_at_jitter);
  const Eigen::Vector3d target_jitter(jitter(rng), jitter(rng), jitter(rng));
  const double r = o.orbit_radius;
  switch (o.path) {
    case SyntheticOptions::Path::kOrbit: {
      const double a = (t - 0.5) * arc;
      const Eigen::Vector3d center(r * std::sin(a), -0.1 * r * std::sin(3 * a), -r * std::cos(a));
      return LookAt(center, target_jitter);
    }
    case SyntheticOptions::Path::kForward: {
      const Eigen::Vector3d center(0.1 * r * std::sin(6 * t), 0.05 * r * std::cos(5 * t),
                                   -r * (1.0 - 0.4 * t));
      return LookAt(center, center + Eigen::Vector3d(0, 0, r) + target_jitter);
    }
    case SyntheticOptions::Path::kSideways: {
      const double x = (t - 0.5) * 2.0 * o.scene_extent;
      const Eigen::Vector3d center(x, 0.0, -r);
      return LookAt(center, Eigen::Vector3d(x, 0, 0) + target_jitter);
    }
    case SyntheticOptions::Path::kPureRotation: {
      const double a = (t - 0.5) * arc;
      const Eigen::Vector3d center(0, 0, -r);
      return LookAt(center, center + Eigen::Vector3d(std::sin(a), 0.05 * std::sin(2 * a),
                                                     std::cos(a)));
    }
  }
  Fail("unknown synthetic path");
}

}  // namespace

SyntheticScene GenerateSyntheticScene(const SyntheticOptions& o) {
  if (o.num_images < 1 || o.num_points < 1 || o.width < 2 || o.height < 2)
    Fail("synthetic scene needs at least one image and one point");
  Rng rng(o.seed);
  SyntheticScene scene;
  scene.points.reserve(o.num_points);
  for (int p = 0; p < o.num_points; ++p) scene.points.push_back(RandomPoint(o, rng));

  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_real_distribution<double> ux(0.0, o.width), uy(0.0, o.height), u01(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, o.noise_sigma > 0 ? o.noise_sigma : 1.0);
  for (int i = 0; i < o.num_images; ++i) {
    const double t = o.num_images > 1 ? static_cast<double>(i) / (o.num_images - 1) : 0.0;
    Camera camera = Camera::FromFocal(o.width, o.height,
                                      o.focal_start + t * (o.focal_end - o.focal_start));
    camera.camera_id = static_cast<camera_t>(i + 1);
    camera.params[Camera::kAspect] = o.aspect;
    camera.params[Camera::kSkew] = o.skew;
    camera.params[Camera::kU0] += o.principal_point_offset * unit(rng);
    camera.params[Camera::kV0] += o.principal_point_offset * unit(rng);
    camera.params[Camera::kK1] = o.k1;
    camera.params[Camera::kK2] = o.k2;
    const Rigid3d pose = PathPose(o, i, rng);

    std::vector<SyntheticObservation> observations;
    for (int p = 0; p < o.num_points; ++p) {
      const Eigen::Vector3d x_cam = pose * scene.points[p];
      if (x_cam.z() < 1e-3 * o.orbit_radius) continue;
      const Eigen::Vector2d pixel = camera.Project(x_cam);
      if (pixel.x() < 0 || pixel.y() < 0 || pixel.x() >= o.width || pixel.y() >= o.height)
        continue;
      SyntheticObservation obs;
      obs.point_id = p;
      obs.true_pixel = pixel;
      obs.pixel = pixel;
      if (o.noise_sigma > 0) obs.pixel += Eigen::Vector2d(noise(rng), noise(rng));
      if (o.outlier_ratio > 0 && u01(rng) < o.outlier_ratio) {
        obs.pixel = Eigen::Vector2d(ux(rng), uy(rng));
        obs.outlier = true;
      }
      observations.push_back(obs);
    }
    scene.cameras.push_back(camera);
    scene.poses.push_back(pose);
    scene.observations.push_back(std::move(observations));
  }
  return scene;
}

void SyntheticScene::Correspondences(int image1, int image2, std::vector<Eigen::Vector2d>* pixels1,
                                     std::vector<Eigen::Vector2d>* pixels2,
                                     std::vector<int>* point_ids) const {
  pixels1->clear();
  pixels2->clear();
  if (point_ids) point_ids->clear();
  std::unordered_map<int, Eigen::Vector2d> seen1;
  for (const auto& obs : observations.at(image1)) seen1.emplace(obs.point_id, obs.pixel);
  for (const auto& obs : observations.at(image2)) {
    const auto it = seen1.find(obs.point_id);
    if (it == seen1.end()) continue;
    pixels1->push_back(it->second);
    pixels2->push_back(obs.pixel);
    if (point_ids) point_ids->push_back(obs.point_id);
  }
}

Eigen::Matrix<double, 3, 4> SyntheticScene::ProjectionMatrix(int image) const {
  return cameras.at(image).K() * poses.at(image).ToMatrix();
}

}  // namespace varsfm
