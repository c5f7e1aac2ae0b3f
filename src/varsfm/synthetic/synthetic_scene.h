#pragma once
// Synthetic scenes with exact ground truth for tests, benchmarks and the demo: 3D points, a
// camera path with per-image intrinsics (zoom sweeps), projections with pixel noise and
// outliers, and the degenerate configurations self-calibration must detect.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "varsfm/camera/camera.h"
#include "varsfm/geometry/rigid3.h"
#include "varsfm/util/random.h"

namespace varsfm {

struct SyntheticOptions {
  enum class Structure {
    kBox,     // points uniform in a cube of side 2*scene_extent around the origin
    kPlane,   // points on the plane z = 0 (a planar scene: homography-explained)
    kFacade,  // a plane with relief of +-20 % of the extent (a building front)
  };
  enum class Path {
    kOrbit,         // arc around the origin at orbit_radius, all looking at the origin
    kForward,       // walk along the viewing direction towards the scene, with lateral sway
    kSideways,      // translate parallel to the scene (a street-side capture)
    kPureRotation,  // one centre, the camera pans (no parallax)
  };

  Structure structure = Structure::kBox;
  Path path = Path::kOrbit;
  int num_images = 10;
  int num_points = 1000;
  int width = 1024;
  int height = 768;
  double scene_extent = 1.0;
  double orbit_radius = 5.0;
  double arc_degrees = 60.0;  // orbit span; pan span for kPureRotation
  // Random offset of each camera's look-at point (scene units). 0 makes every optical axis
  // pass through the origin, the configuration where two-view self-calibration degenerates.
  double look_at_jitter = 0.5;
  // Focal length per image, linear from focal_start to focal_end (a zoom sweep).
  double focal_start = 1000.0;
  double focal_end = 1000.0;
  double aspect = 1.0;
  double skew = 0.0;
  double principal_point_offset = 0.0;  // max random offset (px) of (u0, v0) from the centre
  double k1 = 0.0;
  double k2 = 0.0;
  double noise_sigma = 0.0;    // Gaussian pixel noise on every observation
  double outlier_ratio = 0.0;  // fraction of observations replaced by uniform random pixels
  uint64_t seed = kDefaultSeed;
};

struct SyntheticObservation {
  int point_id = -1;
  Eigen::Vector2d pixel;       // what a detector would see (noise / outlier applied)
  Eigen::Vector2d true_pixel;  // the exact projection
  bool outlier = false;
};

struct SyntheticScene {
  std::vector<Camera> cameras;  // one per image, camera_id = image index + 1
  std::vector<Rigid3d> poses;   // cam_from_world, one per image
  std::vector<Eigen::Vector3d> points;
  // Per image: the points in front of the camera and inside the image.
  std::vector<std::vector<SyntheticObservation>> observations;

  int NumImages() const { return static_cast<int>(cameras.size()); }
  // The points seen in both images, as matched pixel pairs (outliers included).
  void Correspondences(int image1, int image2, std::vector<Eigen::Vector2d>* pixels1,
                       std::vector<Eigen::Vector2d>* pixels2,
                       std::vector<int>* point_ids = nullptr) const;
  // The 3x4 projection matrix K [R | t] of an image (distortion not included).
  Eigen::Matrix<double, 3, 4> ProjectionMatrix(int image) const;
};

SyntheticScene GenerateSyntheticScene(const SyntheticOptions& options);

}  // namespace varsfm
