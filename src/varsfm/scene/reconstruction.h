#pragma once
// The sparse model: cameras (one per image unless intrinsics are shared), images with their
// poses and 2D points, and 3D points with their tracks. Ordered containers keep iteration
// order, and so every result, deterministic.
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "varsfm/camera/camera.h"
#include "varsfm/geometry/rigid3.h"
#include "varsfm/util/types.h"

namespace varsfm {

struct Point2D {
  Eigen::Vector2d xy = Eigen::Vector2d::Zero();
  point3D_t point3D_id = kInvalidPoint3DId;
  bool HasPoint3D() const { return point3D_id != kInvalidPoint3DId; }
};

struct TrackElement {
  image_t image_id = kInvalidImageId;
  point2D_t point2D_idx = kInvalidPoint2DIdx;
};

// The colour of a point no photograph was sampled for (map without its photos, a photo that
// could not be read): mid grey, as the mesh and texture stages show what they cannot colour.
inline const Eigen::Matrix<uint8_t, 3, 1> kUncolouredPoint{128, 128, 128};

struct Point3D {
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero();
  Eigen::Matrix<uint8_t, 3, 1> color = kUncolouredPoint;
  double error = -1.0;  // mean reprojection error (px), -1 when not computed
  std::vector<TrackElement> track;
};

struct Image {
  image_t image_id = kInvalidImageId;
  std::string name;
  camera_t camera_id = 0;
  Rigid3d cam_from_world;
  bool registered = false;
  std::vector<Point2D> points2D;

  size_t NumPoints3D() const;
  Eigen::Vector3d Center() const { return cam_from_world.Center(); }
};

// Told of every change of which 2D points of which registered images have a 3D point, as it
// happens: a 2D point that gains or loses its 3D point, an image registered or unregistered.
// The incremental mapper follows the model through it instead of rescanning every image after
// each registration (sfm/visible_point_counts.h).
class ReconstructionObserver {
 public:
  virtual ~ReconstructionObserver() = default;
  // Point `idx` of `image` now has a 3D point (`triangulated`) or no longer has one.
  virtual void PointTriangulationChanged(const Image& image, point2D_t idx, bool triangulated) = 0;
  // `image` was registered or unregistered (its 2D points keep their 3D points across the call).
  virtual void ImageRegistrationChanged(const Image& image) = 0;
};

class Reconstruction {
 public:
  void AddCamera(const Camera& camera);  // keyed by camera.camera_id
  void AddImage(Image image);            // keyed by image.image_id
  bool ExistsCamera(camera_t id) const { return cameras_.count(id) > 0; }
  bool ExistsImage(image_t id) const { return images_.count(id) > 0; }
  bool ExistsPoint3D(point3D_t id) const { return points3D_.count(id) > 0; }

  Camera& camera(camera_t id) { return cameras_.at(id); }
  const Camera& camera(camera_t id) const { return cameras_.at(id); }
  Image& image(image_t id) { return images_.at(id); }
  const Image& image(image_t id) const { return images_.at(id); }
  Point3D& point3D(point3D_t id) { return points3D_.at(id); }
  const Point3D& point3D(point3D_t id) const { return points3D_.at(id); }
  // The camera of an image.
  Camera& CameraOf(image_t id) { return cameras_.at(images_.at(id).camera_id); }
  const Camera& CameraOf(image_t id) const { return cameras_.at(images_.at(id).camera_id); }

  const std::map<camera_t, Camera>& cameras() const { return cameras_; }
  const std::map<image_t, Image>& images() const { return images_; }
  const std::map<point3D_t, Point3D>& points3D() const { return points3D_; }
  std::map<point3D_t, Point3D>& points3D() { return points3D_; }

  void RegisterImage(image_t id);
  // Unregisters and removes the image's observations from every track.
  void DeRegisterImage(image_t id);
  std::vector<image_t> RegisteredImageIds() const;
  size_t NumRegisteredImages() const;

  // Adds a point and links every track element's 2D point to it. Returns its id. (A default
  // of `{}` would leave the colour uninitialised: Eigen's fixed-size default constructor does
  // not set its coefficients.)
  point3D_t AddPoint3D(const Eigen::Vector3d& xyz, std::vector<TrackElement> track,
                       const Eigen::Matrix<uint8_t, 3, 1>& color = kUncolouredPoint);
  void AddObservation(point3D_t point3D_id, const TrackElement& element);
  // Removes one observation; the point goes too when fewer than two remain.
  void DeleteObservation(image_t image_id, point2D_t point2D_idx);
  void DeletePoint3D(point3D_t point3D_id);
  // Merges two points (tracks joined, position averaged by track length). Returns the kept id.
  point3D_t MergePoints3D(point3D_t point3D_id1, point3D_t point3D_id2);

  // Reprojection of a point in an image (through the image's camera, with distortion).
  // Returns false when the point is behind the camera.
  bool Project(image_t image_id, const Eigen::Vector3d& xyz, Eigen::Vector2d* pixel) const;
  // Squared reprojection error of one observation; +inf when behind the camera.
  double SquaredReprojectionError(const TrackElement& element, const Eigen::Vector3d& xyz) const;

  size_t NumObservations() const;
  double MeanTrackLength() const;
  // Updates Point3D::error of every point and returns the mean / RMS over all observations.
  double UpdatePointErrors();
  double RmsReprojectionError() const;
  double MeanReprojectionError() const;

  // Filters (return the number of observations removed). `image_ids` empty means all images.
  size_t FilterObservationsWithLargeError(double max_error_px,
                                          const std::vector<image_t>& image_ids = {});
  size_t FilterPointsWithSmallTriangulationAngle(double min_angle_deg,
                                                 const std::vector<image_t>& image_ids = {});
  // Removes the points seen by exactly two images with an observation's reprojection error above
  // max_error_px; returns the number of points removed.
  size_t FilterTwoViewPointsWithLargeError(double max_error_px);

  // The observer told of every change from now on (null: none). It belongs to this object, not
  // to its contents: a copy starts without one, and an assignment, which replaces the contents
  // without telling, keeps this object's (so an observed model must not be assigned to).
  void SetObserver(ReconstructionObserver* observer) { observer_.observer = observer; }

 private:
  struct ObserverSlot {
    ReconstructionObserver* observer = nullptr;
    ObserverSlot() = default;
    ObserverSlot(const ObserverSlot&) {}
    ObserverSlot& operator=(const ObserverSlot&) { return *this; }
  };
  // Sets the 2D point's 3D point id, telling the observer when whether it has one changes.
  void SetPoint3DId(const TrackElement& element, point3D_t point3D_id);

  std::map<camera_t, Camera> cameras_;
  std::map<image_t, Image> images_;
  std::map<point3D_t, Point3D> points3D_;
  point3D_t next_point3D_id_ = 1;
  ObserverSlot observer_;
};

}  // namespace varsfm
