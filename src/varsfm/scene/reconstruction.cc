#include "varsfm/scene/reconstruction.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <unordered_map>

#include "varsfm/util/error.h"

namespace varsfm {
namespace {

double AngleBetweenRays(const Eigen::Vector3d& c1, const Eigen::Vector3d& c2,
                        const Eigen::Vector3d& x) {
  const Eigen::Vector3d r1 = (x - c1).normalized(), r2 = (x - c2).normalized();
  return std::acos(std::clamp(r1.dot(r2), -1.0, 1.0));
}

}  // namespace

size_t Image::NumPoints3D() const {
  return std::count_if(points2D.begin(), points2D.end(),
                       [](const Point2D& p) { return p.HasPoint3D(); });
}

void Reconstruction::AddCamera(const Camera& camera) { cameras_[camera.camera_id] = camera; }

void Reconstruction::AddImage(Image image) {
  if (!ExistsCamera(image.camera_id))
    Fail("image {} refers to camera {}, which is not in the model", image.name, image.camera_id);
  const image_t id = image.image_id;
  images_[id] = std::move(image);
}

void Reconstruction::RegisterImage(image_t id) {
  Image& image = images_.at(id);
  if (image.registered) return;
  image.registered = true;
  if (observer_.observer) observer_.observer->ImageRegistrationChanged(image);
}

void Reconstruction::DeRegisterImage(image_t id) {
  Image& image = images_.at(id);
  for (point2D_t idx = 0; idx < image.points2D.size(); ++idx)
    if (image.points2D[idx].HasPoint3D()) DeleteObservation(id, idx);
  if (!image.registered) return;
  image.registered = false;
  if (observer_.observer) observer_.observer->ImageRegistrationChanged(image);
}

void Reconstruction::SetPoint3DId(const TrackElement& element, point3D_t point3D_id) {
  Image& image = images_.at(element.image_id);
  Point2D& p2 = image.points2D.at(element.point2D_idx);
  const bool had = p2.HasPoint3D();
  p2.point3D_id = point3D_id;
  if (observer_.observer && had != p2.HasPoint3D())
    observer_.observer->PointTriangulationChanged(image, element.point2D_idx, p2.HasPoint3D());
}

std::vector<image_t> Reconstruction::RegisteredImageIds() const {
  std::vector<image_t> ids;
  for (const auto& [id, image] : images_)
    if (image.registered) ids.push_back(id);
  return ids;
}

size_t Reconstruction::NumRegisteredImages() const { return RegisteredImageIds().size(); }

point3D_t Reconstruction::AddPoint3D(const Eigen::Vector3d& xyz, std::vector<TrackElement> track,
                                     const Eigen::Matrix<uint8_t, 3, 1>& color) {
  const point3D_t id = next_point3D_id_++;
  for (const auto& el : track) SetPoint3DId(el, id);
  Point3D& point = points3D_[id];
  point.xyz = xyz;
  point.color = color;
  point.track = std::move(track);
  return id;
}

void Reconstruction::AddObservation(point3D_t point3D_id, const TrackElement& element) {
  SetPoint3DId(element, point3D_id);
  points3D_.at(point3D_id).track.push_back(element);
}

void Reconstruction::DeleteObservation(image_t image_id, point2D_t point2D_idx) {
  const point3D_t id = images_.at(image_id).points2D.at(point2D_idx).point3D_id;
  if (id == kInvalidPoint3DId) return;
  SetPoint3DId({image_id, point2D_idx}, kInvalidPoint3DId);
  auto& track = points3D_.at(id).track;
  std::erase_if(track, [&](const TrackElement& el) {
    return el.image_id == image_id && el.point2D_idx == point2D_idx;
  });
  if (track.size() < 2) DeletePoint3D(id);
}

void Reconstruction::DeletePoint3D(point3D_t point3D_id) {
  const auto it = points3D_.find(point3D_id);
  if (it == points3D_.end()) return;
  for (const auto& el : it->second.track) SetPoint3DId(el, kInvalidPoint3DId);
  points3D_.erase(it);
}

point3D_t Reconstruction::MergePoints3D(point3D_t id1, point3D_t id2) {
  Point3D& p1 = points3D_.at(id1);
  Point3D& p2 = points3D_.at(id2);
  const double w1 = static_cast<double>(p1.track.size()), w2 = static_cast<double>(p2.track.size());
  p1.xyz = (w1 * p1.xyz + w2 * p2.xyz) / (w1 + w2);
  for (const auto& el : p2.track) {
    SetPoint3DId(el, id1);
    p1.track.push_back(el);
  }
  points3D_.erase(id2);
  return id1;
}

namespace {

bool ProjectThrough(const Image& image, const Camera& camera, const Eigen::Vector3d& xyz,
                    Eigen::Vector2d* pixel) {
  const Eigen::Vector3d x_cam = image.cam_from_world * xyz;
  if (x_cam.z() <= std::numeric_limits<double>::epsilon()) return false;
  *pixel = camera.Project(x_cam);
  return true;
}

double SquaredErrorThrough(const Image& image, const Camera& camera, point2D_t point2D_idx,
                           const Eigen::Vector3d& xyz) {
  Eigen::Vector2d pixel;
  if (!ProjectThrough(image, camera, xyz, &pixel)) return std::numeric_limits<double>::infinity();
  return (pixel - image.points2D.at(point2D_idx).xy).squaredNorm();
}

}  // namespace

bool Reconstruction::Project(image_t image_id, const Eigen::Vector3d& xyz,
                             Eigen::Vector2d* pixel) const {
  const Image& image = images_.at(image_id);
  return ProjectThrough(image, cameras_.at(image.camera_id), xyz, pixel);
}

double Reconstruction::SquaredReprojectionError(const TrackElement& el,
                                                const Eigen::Vector3d& xyz) const {
  const Image& image = images_.at(el.image_id);
  return SquaredErrorThrough(image, cameras_.at(image.camera_id), el.point2D_idx, xyz);
}

size_t Reconstruction::NumObservations() const {
  size_t n = 0;
  for (const auto& [id, point] : points3D_) n += point.track.size();
  return n;
}

double Reconstruction::MeanTrackLength() const {
  return points3D_.empty() ? 0.0 : static_cast<double>(NumObservations()) / points3D_.size();
}

double Reconstruction::UpdatePointErrors() {
  double sum = 0;
  size_t n = 0;
  for (auto& [id, point] : points3D_) {
    double point_sum = 0;
    for (const auto& el : point.track)
      point_sum += std::sqrt(SquaredReprojectionError(el, point.xyz));
    point.error = point.track.empty() ? -1.0 : point_sum / point.track.size();
    sum += point_sum;
    n += point.track.size();
  }
  return n ? sum / n : 0.0;
}

double Reconstruction::RmsReprojectionError() const {
  double sum_sq = 0;
  size_t n = 0;
  for (const auto& [id, point] : points3D_)
    for (const auto& el : point.track) {
      sum_sq += SquaredReprojectionError(el, point.xyz);
      ++n;
    }
  return n ? std::sqrt(sum_sq / n) : 0.0;
}

double Reconstruction::MeanReprojectionError() const {
  double sum = 0;
  size_t n = 0;
  for (const auto& [id, point] : points3D_)
    for (const auto& el : point.track) {
      sum += std::sqrt(SquaredReprojectionError(el, point.xyz));
      ++n;
    }
  return n ? sum / n : 0.0;
}

namespace {

// The images a filter visits, each looked up in the model's maps once per call instead of the
// image and its camera once per observation: on a long sequence those are std::maps of
// thousands of entries and the lookups a fifth of the work around each local adjustment
// (docs/measurements.md). Node-based maps keep the pointers valid while observations are
// deleted.
class ViewCache {
 public:
  struct View {
    const Image* image = nullptr;
    const Camera* camera = nullptr;
    std::optional<Eigen::Vector3d> center;
  };
  ViewCache(const std::map<image_t, Image>& images, const std::map<camera_t, Camera>& cameras)
      : images_(images), cameras_(cameras) {}
  View& Get(image_t id) {
    auto [it, inserted] = views_.try_emplace(id);
    if (inserted) {
      it->second.image = &images_.at(id);
      it->second.camera = &cameras_.at(it->second.image->camera_id);
    }
    return it->second;
  }
  double SquaredError(const TrackElement& el, const Eigen::Vector3d& xyz) {
    const View& view = Get(el.image_id);
    return SquaredErrorThrough(*view.image, *view.camera, el.point2D_idx, xyz);
  }
  const Eigen::Vector3d& Center(image_t id) {
    View& view = Get(id);
    if (!view.center) view.center = view.image->Center();
    return *view.center;
  }

 private:
  const std::map<image_t, Image>& images_;
  const std::map<camera_t, Camera>& cameras_;
  std::unordered_map<image_t, View> views_;
};

// The ids of the points observed in `image_ids` (every point when empty).
std::vector<point3D_t> PointsSeenBy(const Reconstruction& rec, const std::vector<image_t>& ids) {
  std::vector<point3D_t> out;
  if (ids.empty()) {
    for (const auto& [id, point] : rec.points3D()) out.push_back(id);
    return out;
  }
  for (const image_t image_id : ids)
    for (const auto& p2 : rec.image(image_id).points2D)
      if (p2.HasPoint3D()) out.push_back(p2.point3D_id);
  std::sort(out.begin(), out.end());  // ascending, each once
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace

size_t Reconstruction::FilterObservationsWithLargeError(double max_error_px,
                                                        const std::vector<image_t>& image_ids) {
  const double max_sq = max_error_px * max_error_px;
  size_t removed = 0;
  ViewCache views(images_, cameras_);
  for (const point3D_t id : PointsSeenBy(*this, image_ids)) {
    const auto it = points3D_.find(id);
    if (it == points3D_.end()) continue;
    const auto too_far = [&](const TrackElement& el) {
      return views.SquaredError(el, it->second.xyz) > max_sq;
    };
    if (std::none_of(it->second.track.begin(), it->second.track.end(), too_far)) continue;
    const Point3D point = it->second;  // copy: DeleteObservation edits the track
    for (const auto& el : point.track) {
      if (views.SquaredError(el, point.xyz) <= max_sq) continue;
      DeleteObservation(el.image_id, el.point2D_idx);
      ++removed;
      if (!ExistsPoint3D(id)) break;
    }
  }
  return removed;
}

size_t Reconstruction::FilterTwoViewPointsWithLargeError(double max_error_px) {
  const double max_sq = max_error_px * max_error_px;
  ViewCache views(images_, cameras_);
  std::vector<point3D_t> removed;
  for (const auto& [id, point] : points3D_) {
    if (point.track.size() != 2) continue;
    if (views.SquaredError(point.track[0], point.xyz) > max_sq ||
        views.SquaredError(point.track[1], point.xyz) > max_sq)
      removed.push_back(id);
  }
  for (const point3D_t id : removed) DeletePoint3D(id);
  return removed.size();
}

size_t Reconstruction::FilterPointsWithSmallTriangulationAngle(
    double min_angle_deg, const std::vector<image_t>& image_ids) {
  const double min_angle = min_angle_deg * std::numbers::pi / 180.0;
  size_t removed = 0;
  ViewCache views(images_, cameras_);
  std::vector<Eigen::Vector3d> centers;
  for (const point3D_t id : PointsSeenBy(*this, image_ids)) {
    const Point3D& point = points3D_.at(id);
    centers.clear();
    for (const auto& el : point.track) centers.push_back(views.Center(el.image_id));
    double max_angle = 0;
    for (size_t i = 0; i < centers.size() && max_angle < min_angle; ++i)
      for (size_t j = i + 1; j < centers.size() && max_angle < min_angle; ++j)
        max_angle = std::max(max_angle, AngleBetweenRays(centers[i], centers[j], point.xyz));
    if (max_angle >= min_angle) continue;
    removed += point.track.size();
    DeletePoint3D(id);
  }
  return removed;
}

}  // namespace varsfm
