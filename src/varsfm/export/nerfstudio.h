#pragma once
// Export for nerfstudio (Tancik et al. 2023): DIR/transforms.json, the photos in DIR/images and
// the sparse points in DIR/sparse_pc.ply (splatfacto's initialisation). nerfstudio's format
// allows intrinsics on each frame (fl_x, fl_y, cx, cy, w, h, k1, k2, p1, p2), which a camera
// whose zoom changes needs; the photos are copied as they are and their radial distortion is
// given as the OPENCV model's k1, k2 (the same polynomial on normalised coordinates as varsfm's).
#include <filesystem>

#include <nlohmann/json.hpp>

#include "varsfm/scene/reconstruction.h"

namespace varsfm {

// The camera-to-world matrix nerfstudio expects for an image (OpenGL camera axes: x right,
// y up, z backwards), in the model's own world frame.
Eigen::Matrix4d NerfstudioCameraToWorld(const Image& image);

// transforms.json for the registered images, file paths "images/<name>", in image-id order.
nlohmann::json NerfstudioTransforms(const Reconstruction& reconstruction);

struct NerfstudioExportSummary {
  size_t num_frames = 0;
  size_t num_points = 0;
};

// Writes DIR/transforms.json, DIR/images/<name> (copies) and DIR/sparse_pc.ply. `output` must
// not exist or be empty; it appears complete or not at all. Throws varsfm::Error (one line) for
// a missing photo or an unwritable output.
NerfstudioExportSummary ExportNerfstudio(const Reconstruction& reconstruction,
                                         const std::filesystem::path& image_dir,
                                         const std::filesystem::path& output);

}  // namespace varsfm
