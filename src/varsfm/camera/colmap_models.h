#pragma once
// Mapping between varsfm's camera (f, aspect e, skew s, u0, v0, k1, k2) and COLMAP's camera
// models (ids and parameter orders as in COLMAP's src/base/camera_models.h):
//
//   id name            params                              varsfm holds
//   0  SIMPLE_PINHOLE  f, cx, cy                           e = 1, k1 = k2 = 0
//   1  PINHOLE         fx, fy, cx, cy                      k1 = k2 = 0       (e = fy / fx)
//   2  SIMPLE_RADIAL   f, cx, cy, k                        e = 1, k2 = 0
//   3  RADIAL          f, cx, cy, k1, k2                   e = 1
//   4  OPENCV          fx, fy, cx, cy, k1, k2, p1, p2      p1 = p2 = 0 on export
//   6  FULL_OPENCV     fx, fy, cx, cy, k1, k2, p1, p2, k3..k6   (import only, p, k3.. dropped)
//
// No COLMAP model has skew; a camera with non-zero skew is exported without it (a warning is
// logged), which is why skew is held at 0 unless asked otherwise.
#include <string>
#include <vector>

#include "varsfm/camera/camera.h"

namespace varsfm {

inline constexpr int kColmapSimplePinhole = 0;
inline constexpr int kColmapPinhole = 1;
inline constexpr int kColmapSimpleRadial = 2;
inline constexpr int kColmapRadial = 3;
inline constexpr int kColmapOpenCV = 4;
inline constexpr int kColmapFullOpenCV = 6;

std::string ColmapModelName(int model_id);           // "" for unknown ids
int ColmapModelIdFromName(const std::string& name);  // -1 for unknown names

// The simplest COLMAP model that represents the camera exactly (up to skew).
int SmallestColmapModel(const Camera& camera);

// The camera's parameters in `model_id`'s order. Parameters the model lacks must be at their
// held values (e.g. k2 = 0 for SIMPLE_RADIAL) or they are lost: call SmallestColmapModel first.
std::vector<double> ToColmapParams(const Camera& camera, int model_id);

// Throws varsfm::Error for models varsfm cannot represent (fisheye models) or a wrong count.
Camera CameraFromColmap(int model_id, const std::vector<double>& params, int width, int height);

}  // namespace varsfm
