#pragma once
// A synthetic textured scene rendered as photographs, with exact ground truth: the built-in
// demo input. A room corner (back wall, floor, side wall) and two boxes, every face covered by
// a procedural texture with blobs at several scales (what SIFT responds to), filmed along an
// orbit by a camera that zooms (focal length x1.0 -> x1.6); or a long street (CameraPath). Radial
// distortion can be added, but the Strecha ground-truth layout cannot record it, so the demo
// renders without.
#include <filesystem>
#include <vector>

#include <opencv2/core.hpp>

#include "varsfm/camera/camera.h"
#include "varsfm/geometry/rigid3.h"
#include "varsfm/util/option_check.h"
#include "varsfm/util/random.h"

namespace varsfm {

// How the camera moves. kOrbit: around the room corner, over arc_degrees for the whole
// sequence (the demo). kStreet: along a facade that goes on as far as the sequence needs, a
// fixed step per image, the zoom going in and out every 100 images: each point stays in view
// for a bounded number of images however long the sequence, as in a video walked or flown
// along a street (bench/scale's long sequences). kStreetAndBack: the first half of the images
// along the street, the second half back to the start 1 m nearer the facade, looking the other
// way ahead: a walk whose end overlaps its start (loop closure). kPhotos: the street of
// kStreet's length, photographed from independent random positions (3-5 m from the facade)
// in random directions (yaw within 35 deg of the facade's normal, pitch from the aimed height)
// with a random focal length from x1 to x`zoom`: an unordered photo collection, whose image
// index says nothing about where it was taken.
enum class CameraPath { kOrbit, kStreet, kStreetAndBack, kPhotos };

struct RenderedSceneOptions {
  CameraPath path = CameraPath::kOrbit;
  double street_step = 0.1;  // kStreet, kPhotos: metres of street per image
  int num_images = 12;
  int width = 800;
  int height = 600;
  double focal_start = 640.0;
  double zoom = 1.6;  // the last image's focal length is zoom x focal_start
  double k1 = 0.0;
  double arc_degrees = 50.0;
  int supersampling = 2;  // per axis
  uint64_t seed = kDefaultSeed;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

// A flat face of the scene: origin + s u + t v for s, t in [0, 1].
struct SurfaceQuad {
  Eigen::Vector3d origin, u, v;
};

struct RenderedScene {
  std::vector<cv::Mat> images;  // BGR, 8-bit
  std::vector<Camera> cameras;
  std::vector<Rigid3d> poses;        // cam_from_world
  std::vector<SurfaceQuad> surface;  // every face of the scene: the exact truth
};

// `check`: kDoneByCaller when the caller checked `options` (the demo stage).
RenderedScene RenderSyntheticScene(const RenderedSceneOptions& options,
                                   OptionsCheck check = OptionsCheck::kByStage);

// Writes images as IMAGE_0000.png ... into `image_dir` and the ground truth in the Strecha
// layout (NAME.camera: K, 0 0 0, R camera-to-world, C, width height; K in Strecha's convention,
// pixel centre at (0, 0)) into `gt_dir`.
void WriteRenderedScene(const RenderedScene& scene, const std::filesystem::path& image_dir,
                        const std::filesystem::path& gt_dir);

}  // namespace varsfm
