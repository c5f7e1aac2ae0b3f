#pragma once
// Ground-truth cameras of the Strecha et al. benchmark (CVPR 2008): one NAME.camera file per
// image (e.g. 0000.jpg.camera for 0000.jpg), rows
//   K (3 rows)      pixels, (0, 0) at the centre of the top-left pixel
//   0 0 0           no distortion
//   R (3 rows)      camera-to-world: X_world = R X_cam + C
//   C               camera centre, metres
//   width height
// Converted on reading to varsfm's conventions: principal point + 0.5 px, world-to-camera pose.
#include <filesystem>
#include <map>
#include <string>

#include "varsfm/camera/camera.h"
#include "varsfm/geometry/rigid3.h"

namespace varsfm {

struct GroundTruthCamera {
  std::string name;  // the image file name ("0000.jpg")
  Camera camera;     // K in varsfm's pixel convention, no distortion
  Rigid3d cam_from_world;
  Eigen::Vector3d Center() const { return cam_from_world.Center(); }
};

struct GroundTruth {
  std::map<std::string, GroundTruthCamera> cameras;  // by image name
};

// Reads one .camera file; `name` is the file name without ".camera". Throws varsfm::Error
// naming the file when it is malformed (short, non-numeric, K(2,2) != 1, R not a rotation).
GroundTruthCamera ReadStrechaCamera(const std::filesystem::path& file);

// Reads every *.camera file of `dir`. Throws varsfm::Error if the folder is missing or has none.
GroundTruth ReadStrechaGroundTruth(const std::filesystem::path& dir);

}  // namespace varsfm
