#pragma once
// A registered camera where it stood: its intrinsics and its pose. What the stages that look at
// a mesh from the registered images take of each one (mesh: the long faces judged by the
// views; texture: the views a face is textured from).
#include "varsfm/camera/camera.h"
#include "varsfm/geometry/rigid3.h"

namespace varsfm {

struct PosedCamera {
  Camera camera;
  Rigid3d cam_from_world;
};

}  // namespace varsfm
