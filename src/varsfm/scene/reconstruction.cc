#include "varsfm/scene/reconstruction.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

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

namespace {

// Every image's pose and camera for a pass over observations, looked up in the model's maps once
// per call instead of the image and its camera once per observation: on a long sequence those are
// std::maps of thousands of entries and the lookups a fifth of the work around each local
// adjustment (docs/measurements.md). Read-only, and so shared by the threads, once built. Indexed
// by image id where the ids are dense (a workspace numbers its images from 1), else searched.
class ViewTable {
 public:
  ViewTable(const std::map<image_t, Image>& images, const std::map<camera_t, Camera>& cameras) {
    views_.reserve(images.size());
    for (const auto& [id, image] : images)
      views_.push_back({id, &image, &cameras.at(image.camera_id), image.Center()});
    const size_t max_id = views_.empty() ? 0 : views_.back().id;
    if (max_id <= 4 * views_.size() + 64) {
      slot_.assign(max_id + 1, kNoSlot);
      for (size_t i = 0; i < views_.size(); ++i) slot_[views_[i].id] = static_cast<uint32_t>(i);
    }
  }
  double SquaredError(const TrackElement& el, const Eigen::Vector3d& xyz) const {
    const View& view = Get(el.image_id);
    return SquaredErrorThrough(*view.image, *view.camera, el.point2D_idx, xyz);
  }
  const Eigen::Vector3d& Center(image_t id) const { return Get(id).center; }

 private:
  static constexpr uint32_t kNoSlot = std::numeric_limits<uint32_t>::max();
  struct View {
    image_t id;
    const Image* image;
    const Camera* camera;
    Eigen::Vector3d center;
  };
  const View& Get(image_t id) const {
    if (!slot_.empty()) {
      if (id < slot_.size() && slot_[id] != kNoSlot) return views_[slot_[id]];
    } else {
      const auto it = std::lower_bound(views_.begin(), views_.end(), id,
                                       [](const View& v, image_t i) { return v.id < i; });
      if (it != views_.end() && it->id == id) return *it;
    }
    Fail("an observation refers to image {}, which is not in the model", id);
  }
  std::vector<View> views_;     // in id order
  std::vector<uint32_t> slot_;  // per id: its index in views_ (dense ids only)
};

// f(i) for i in [0, n), in parallel. Each call writes only its own results, so every result is
// the same for any thread count; what depends on order (sums, deletions) runs after, in order.
template <typename F>
void ForEachIndex(size_t n, F&& f) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 256), [&](const auto& range) {
    for (size_t i = range.begin(); i != range.end(); ++i) f(i);
  });
}

// Every observation's squared reprojection error, point after point, each point's in track
// order: the order in which the sums below were always taken, so they keep their bits.
std::vector<double> SquaredErrors(const std::vector<const Point3D*>& points,
                                  const ViewTable& views) {
  std::vector<size_t> begin(points.size() + 1, 0);
  for (size_t i = 0; i < points.size(); ++i) begin[i + 1] = begin[i] + points[i]->track.size();
  std::vector<double> errors(begin.back());
  ForEachIndex(points.size(), [&](size_t i) {
    const Point3D& point = *points[i];
    for (size_t k = 0; k < point.track.size(); ++k)
      errors[begin[i] + k] = views.SquaredError(point.track[k], point.xyz);
  });
  return errors;
}

template <typename Map>
auto AllPoints(Map& points3D) {
  std::vector<decltype(&points3D.begin()->second)> out;
  out.reserve(points3D.size());
  for (auto& [id, point] : points3D) out.push_back(&point);
  return out;
}

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

double Reconstruction::UpdatePointErrors() {
  const std::vector<Point3D*> points = AllPoints(points3D_);
  const std::vector<const Point3D*> read(points.begin(), points.end());
  const std::vector<double> errors = SquaredErrors(read, ViewTable(images_, cameras_));
  double sum = 0;
  size_t k = 0;
  for (Point3D* point : points) {
    double point_sum = 0;
    for (size_t j = 0; j < point->track.size(); ++j) point_sum += std::sqrt(errors[k++]);
    point->error = point->track.empty() ? -1.0 : point_sum / point->track.size();
    sum += point_sum;
  }
  return errors.empty() ? 0.0 : sum / errors.size();
}

double Reconstruction::RmsReprojectionError() const {
  const std::vector<const Point3D*> points = AllPoints(points3D_);
  double sum_sq = 0;
  const std::vector<double> errors = SquaredErrors(points, ViewTable(images_, cameras_));
  for (const double e : errors) sum_sq += e;
  return errors.empty() ? 0.0 : std::sqrt(sum_sq / errors.size());
}

double Reconstruction::MeanReprojectionError() const {
  const std::vector<const Point3D*> points = AllPoints(points3D_);
  double sum = 0;
  const std::vector<double> errors = SquaredErrors(points, ViewTable(images_, cameras_));
  for (const double e : errors) sum += std::sqrt(e);
  return errors.empty() ? 0.0 : sum / errors.size();
}

// Both filters judge every point first, in parallel, then edit the model in point order: a
// point's verdict depends on its own position and track only, which no other point's deletion
// changes, so the result is the one of a single pass.
size_t Reconstruction::FilterObservationsWithLargeError(double max_error_px,
                                                        const std::vector<image_t>& image_ids) {
  const double max_sq = max_error_px * max_error_px;
  std::vector<const Point3D*> points;
  std::vector<point3D_t> ids;
  for (const point3D_t id : PointsSeenBy(*this, image_ids)) {
    const auto it = points3D_.find(id);
    if (it == points3D_.end()) continue;
    ids.push_back(id);
    points.push_back(&it->second);
  }
  const ViewTable views(images_, cameras_);
  std::vector<uint8_t> any_large(points.size(), 0);
  ForEachIndex(points.size(), [&](size_t i) {
    any_large[i] = std::any_of(
        points[i]->track.begin(), points[i]->track.end(),
        [&](const TrackElement& el) { return views.SquaredError(el, points[i]->xyz) > max_sq; });
  });
  size_t removed = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    if (!any_large[i]) continue;
    const Point3D point = *points[i];  // copy: DeleteObservation edits the track
    for (const auto& el : point.track) {
      if (views.SquaredError(el, point.xyz) <= max_sq) continue;
      DeleteObservation(el.image_id, el.point2D_idx);
      ++removed;
      if (!ExistsPoint3D(ids[i])) break;
    }
  }
  return removed;
}

size_t Reconstruction::FilterTwoViewPointsWithLargeError(double max_error_px) {
  const double max_sq = max_error_px * max_error_px;
  const ViewTable views(images_, cameras_);
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
  const std::vector<point3D_t> ids = PointsSeenBy(*this, image_ids);
  std::vector<const Point3D*> points(ids.size());
  for (size_t i = 0; i < ids.size(); ++i) points[i] = &points3D_.at(ids[i]);
  const ViewTable views(images_, cameras_);
  std::vector<uint8_t> too_small(points.size(), 0);
  ForEachIndex(points.size(), [&](size_t i) {
    const Point3D& point = *points[i];
    double max_angle = 0;
    for (size_t a = 0; a < point.track.size() && max_angle < min_angle; ++a)
      for (size_t b = a + 1; b < point.track.size() && max_angle < min_angle; ++b)
        max_angle =
            std::max(max_angle, AngleBetweenRays(views.Center(point.track[a].image_id),
                                                 views.Center(point.track[b].image_id), point.xyz));
    too_small[i] = max_angle < min_angle;
  });
  size_t removed = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    if (!too_small[i]) continue;
    removed += points[i]->track.size();
    DeletePoint3D(ids[i]);
  }
  return removed;
}

}  // namespace varsfm
