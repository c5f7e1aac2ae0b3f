#include "varsfm/report/viewer_scene.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Core>

#include "varsfm/report/base64.h"
#include "varsfm/report/report_charts.h"
#include "varsfm/util/statistics.h"

namespace varsfm {
namespace {

nlohmann::json Array(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// The view's vertical field of view, and the width / height of the viewer on a typical screen
// (the page's layout), for the initial framing.
constexpr double kVerticalFovDeg = 50;
constexpr double kViewAspect = 1.25;

// The scene's middle: the per-axis median of the points (robust to stray points), or of the
// camera centres when there are no points.
Eigen::Vector3d SceneCenter(const ReportData& data, const std::vector<Eigen::Vector3d>& centers) {
  std::vector<double> axis[3];
  for (const auto& p : data.view_points)
    for (int k = 0; k < 3; ++k) axis[k].push_back(p[k]);
  if (axis[0].empty())
    for (const auto& c : centers)
      for (int k = 0; k < 3; ++k) axis[k].push_back(c[k]);
  return {Median(axis[0]), Median(axis[1]), Median(axis[2])};
}

// The frustums' depth: a tenth of the typical camera-to-scene distance, but no more than the
// typical spacing of neighbouring cameras, so that a long sequence's frustums do not overlap.
double FrustumDepth(const std::vector<Eigen::Vector3d>& centers, const Eigen::Vector3d& target) {
  std::vector<double> distances;
  for (const auto& c : centers) distances.push_back((c - target).norm());
  double depth = 0.12 * Median(distances);
  if (centers.size() >= 2 && centers.size() <= 3000) {
    std::vector<double> nearest;
    for (size_t i = 0; i < centers.size(); ++i) {
      double best = INFINITY;
      for (size_t j = 0; j < centers.size(); ++j)
        if (j != i) best = std::min(best, (centers[i] - centers[j]).norm());
      nearest.push_back(best);
    }
    const double spacing = Median(nearest);
    if (spacing > 0) depth = std::min(depth, 1.5 * spacing);
  }
  return depth > 0 ? depth : 1.0;
}

nlohmann::json PointsJson(const ReportData& data) {
  std::vector<float> xyz;
  std::vector<uint8_t> rgb;
  for (size_t i = 0; i < data.view_points.size(); ++i) {
    xyz.insert(xyz.end(), data.view_points[i].begin(), data.view_points[i].end());
    rgb.insert(rgb.end(), data.view_colors[i].begin(), data.view_colors[i].end());
  }
  // Little-endian float32, which is what every browser's Float32Array reads on the hosts
  // varsfm builds for.
  return {{"count", data.view_points.size()},
          {"xyz", Base64Encode(reinterpret_cast<const uint8_t*>(xyz.data()), xyz.size() * 4)},
          {"rgb", Base64Encode(rgb)}};
}

}  // namespace

nlohmann::json ViewerSceneJson(const ReportData& data) {
  std::vector<Eigen::Vector3d> centers;
  Eigen::Vector3d up = Eigen::Vector3d::Zero(), forward = Eigen::Vector3d::Zero();
  for (const ReportImage& image : data.images) {
    if (!image.registered) continue;
    centers.push_back(image.cam_from_world.Center());
    const Eigen::Matrix3d world_from_cam = image.cam_from_world.R().transpose();
    up += world_from_cam * Eigen::Vector3d(0, -1, 0);  // image rows grow downwards
    forward += world_from_cam * Eigen::Vector3d::UnitZ();
  }
  const Eigen::Vector3d target = SceneCenter(data, centers);
  const double depth = FrustumDepth(centers, target);
  up = up.norm() > 0 ? up.normalized() : Eigen::Vector3d(0, -1, 0);

  nlohmann::json cameras = nlohmann::json::array();
  const std::vector<std::string> colors = FocalColors(data);
  const double shortest = FocalRange(data).first;
  const bool in_pixels = FocalLengthsInPixels(data);
  for (size_t i = 0; i < data.images.size(); ++i) {
    const ReportImage& image = data.images[i];
    if (!image.registered) continue;
    const Camera& cam = image.camera;
    const Eigen::Matrix3d world_from_cam = image.cam_from_world.R().transpose();
    const Eigen::Vector3d center = image.cam_from_world.Center();
    nlohmann::json corners = nlohmann::json::array();
    // Image corners (0,0), (w,0), (w,h), (0,h) on the plane at `depth` in front of the camera:
    // a longer focal length gives a narrower frustum, so the zoom shows in the drawing.
    for (const auto& [u, v] : {std::pair{0.0, 0.0},
                               {1.0 * cam.width, 0.0},
                               {1.0 * cam.width, 1.0 * cam.height},
                               {0.0, 1.0 * cam.height}}) {
      const Eigen::Vector3d ray((u - cam.params[Camera::kU0]) / cam.focal(),
                                (v - cam.params[Camera::kV0]) / cam.fy(), 1.0);
      corners.push_back(Array(center + world_from_cam * (depth * ray)));
    }
    cameras.push_back({{"id", image.image_id},
                       {"name", image.name},
                       {"center", Array(center)},
                       {"corners", corners},
                       {"color", colors[i]},
                       {"focal", cam.focal()},
                       {"ratio", shortest > 0 ? ComparableFocal(cam, in_pixels) / shortest : 1.0},
                       {"k1", cam.params[Camera::kK1]},
                       {"k2", cam.params[Camera::kK2]},
                       {"pp", {cam.params[Camera::kU0], cam.params[Camera::kV0]}},
                       {"size", {cam.width, cam.height}},
                       {"points", image.num_points3D},
                       {"rms", image.rms_error_px}});
  }

  // Framing: from the target towards the cameras' mean centre and beyond, raised along up, far
  // enough for every camera and nearly all points to be in view.
  Eigen::Vector3d mean_center = Eigen::Vector3d::Zero();
  for (const auto& c : centers) mean_center += c / static_cast<double>(centers.size());
  Eigen::Vector3d away = mean_center - target;
  if (away.norm() < 1e-9 * (1 + target.norm()))
    away = forward.norm() > 0 ? Eigen::Vector3d(-forward.normalized()) : Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d direction = (away.normalized() + 0.35 * up).normalized();  // to the eye
  Eigen::Vector3d right = up.cross(direction);
  right = right.norm() > 1e-9 ? right.normalized() : direction.unitOrthogonal();
  const Eigen::Vector3d view_up = direction.cross(right);
  const double tan_half = std::tan(kVerticalFovDeg * M_PI / 360);
  // The eye's distance from the target at which x is in view: x's depth towards the eye plus
  // its offset across the view over the half field's tangent.
  const auto fit = [&](const Eigen::Vector3d& x) {
    const Eigen::Vector3d d = x - target;
    return d.dot(direction) + std::max(std::abs(d.dot(view_up)) / tan_half,
                                       std::abs(d.dot(right)) / (tan_half * kViewAspect));
  };
  double distance = 0;
  std::vector<double> spread, point_fits;
  for (const auto& c : centers) {
    distance = std::max(distance, fit(c));
    spread.push_back((c - target).norm());
  }
  for (const auto& p : data.view_points) {
    const Eigen::Vector3d x(p[0], p[1], p[2]);
    point_fits.push_back(fit(x));
    spread.push_back((x - target).norm());
  }
  distance = std::max(distance, Quantile(point_fits, 0.95)) * 1.05;
  const double radius = std::max(1e-6, Quantile(spread, 0.95));
  if (!(distance > 0)) distance = 3 * radius;
  const Eigen::Vector3d eye = target + direction * distance;
  return {{"cameras", cameras},      {"points", PointsJson(data)},
          {"target", Array(target)}, {"eye", Array(eye)},
          {"up", Array(up)},         {"radius", radius},
          {"frustum_depth", depth},  {"fov", kVerticalFovDeg}};
}

}  // namespace varsfm
