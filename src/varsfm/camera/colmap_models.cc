#include "varsfm/camera/colmap_models.h"

#include <array>
#include <cmath>

#include "varsfm/util/error.h"
#include "varsfm/util/log.h"

namespace varsfm {
namespace {

struct ModelInfo {
  int id;
  const char* name;
  size_t num_params;
};
constexpr std::array<ModelInfo, 6> kModels = {{{kColmapSimplePinhole, "SIMPLE_PINHOLE", 3},
                                               {kColmapPinhole, "PINHOLE", 4},
                                               {kColmapSimpleRadial, "SIMPLE_RADIAL", 4},
                                               {kColmapRadial, "RADIAL", 5},
                                               {kColmapOpenCV, "OPENCV", 8},
                                               {kColmapFullOpenCV, "FULL_OPENCV", 12}}};

const ModelInfo* FindModel(int id) {
  for (const auto& m : kModels)
    if (m.id == id) return &m;
  return nullptr;
}

}  // namespace

std::string ColmapModelName(int model_id) {
  const ModelInfo* m = FindModel(model_id);
  return m ? m->name : "";
}

int ColmapModelIdFromName(const std::string& name) {
  for (const auto& m : kModels)
    if (name == m.name) return m.id;
  return -1;
}

int SmallestColmapModel(const Camera& camera) {
  const auto& p = camera.params;
  const bool unit_aspect = p[Camera::kAspect] == 1.0;
  if (p[Camera::kK2] != 0.0) return unit_aspect ? kColmapRadial : kColmapOpenCV;
  if (p[Camera::kK1] != 0.0) return unit_aspect ? kColmapSimpleRadial : kColmapOpenCV;
  return unit_aspect ? kColmapSimplePinhole : kColmapPinhole;
}

std::vector<double> ToColmapParams(const Camera& camera, int model_id) {
  const auto& p = camera.params;
  if (p[Camera::kSkew] != 0.0)
    warn("camera {}: skew {:.3g} is not representable in COLMAP's models and is dropped",
         camera.camera_id, p[Camera::kSkew]);
  const double f = p[Camera::kFocal], fy = camera.fy(), cx = p[Camera::kU0], cy = p[Camera::kV0];
  switch (model_id) {
    case kColmapSimplePinhole:
      return {f, cx, cy};
    case kColmapPinhole:
      return {f, fy, cx, cy};
    case kColmapSimpleRadial:
      return {f, cx, cy, p[Camera::kK1]};
    case kColmapRadial:
      return {f, cx, cy, p[Camera::kK1], p[Camera::kK2]};
    case kColmapOpenCV:
      return {f, fy, cx, cy, p[Camera::kK1], p[Camera::kK2], 0.0, 0.0};
    case kColmapFullOpenCV:
      return {f, fy, cx, cy, p[Camera::kK1], p[Camera::kK2], 0, 0, 0, 0, 0, 0};
    default:
      Fail("COLMAP camera model id {} is not supported for export", model_id);
  }
}

Camera CameraFromColmap(int model_id, const std::vector<double>& v, int width, int height) {
  const ModelInfo* m = FindModel(model_id);
  if (m == nullptr)
    Fail("COLMAP camera model id {} is not supported (fisheye or unknown)", model_id);
  if (v.size() != m->num_params)
    Fail("COLMAP camera model {} expects {} parameters, got {}", m->name, m->num_params, v.size());
  for (const double x : v)
    if (!std::isfinite(x)) Fail("COLMAP {} camera: a parameter is not a finite number", m->name);
  const bool has_fy =
      model_id == kColmapPinhole || model_id == kColmapOpenCV || model_id == kColmapFullOpenCV;
  if (!(v[0] > 0) || (has_fy && !(v[1] > 0)))
    Fail("COLMAP {} camera: the focal length must be positive", m->name);
  if (width <= 0 || height <= 0)
    Fail("COLMAP {} camera: image size {} x {} is not positive", m->name, width, height);
  Camera camera;
  camera.width = width;
  camera.height = height;
  auto& p = camera.params;
  p = {v[0], 1.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  switch (model_id) {
    case kColmapSimplePinhole:
    case kColmapSimpleRadial:
    case kColmapRadial:
      p[Camera::kU0] = v[1];
      p[Camera::kV0] = v[2];
      if (v.size() > 3) p[Camera::kK1] = v[3];
      if (v.size() > 4) p[Camera::kK2] = v[4];
      break;
    default:  // PINHOLE, OPENCV, FULL_OPENCV: fx, fy, cx, cy, [k1, k2, p1, p2, ...]
      p[Camera::kAspect] = v[1] / v[0];
      p[Camera::kU0] = v[2];
      p[Camera::kV0] = v[3];
      if (v.size() > 4) {
        p[Camera::kK1] = v[4];
        p[Camera::kK2] = v[5];
        bool dropped = false;
        for (size_t i = 6; i < v.size(); ++i) dropped |= v[i] != 0.0;
        if (dropped)
          warn("COLMAP {} camera: tangential/higher-order terms dropped (varsfm models k1, k2)",
               m->name);
      }
  }
  return camera;
}

}  // namespace varsfm
