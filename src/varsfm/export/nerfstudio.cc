#include "varsfm/export/nerfstudio.h"

#include "varsfm/export/exported_images.h"
#include "varsfm/image/exif.h"
#include "varsfm/image/image_file.h"
#include "varsfm/io/ply.h"
#include "varsfm/util/atomic_file.h"
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"
#include "varsfm/util/new_folder.h"

namespace varsfm {

Eigen::Matrix4d NerfstudioCameraToWorld(const Image& image) {
  Eigen::Matrix4d world_from_cam = Eigen::Matrix4d::Identity();
  const Rigid3d inverse = image.cam_from_world.Inverse();
  world_from_cam.topLeftCorner<3, 3>() = inverse.rotation.toRotationMatrix();
  world_from_cam.topRightCorner<3, 1>() = inverse.translation;
  // COLMAP's camera looks down +z with y down; OpenGL's down -z with y up.
  world_from_cam.col(1).head<3>() *= -1;
  world_from_cam.col(2).head<3>() *= -1;
  return world_from_cam;
}

nlohmann::json NerfstudioTransforms(const Reconstruction& reconstruction) {
  nlohmann::json frames = nlohmann::json::array();
  bool skew_dropped = false;
  for (const image_t id : reconstruction.RegisteredImageIds()) {
    const Image& image = reconstruction.image(id);
    const Camera& camera = reconstruction.CameraOf(id);
    skew_dropped |= camera.params[Camera::kSkew] != 0.0;
    const Eigen::Matrix4d c2w = NerfstudioCameraToWorld(image);
    nlohmann::json matrix = nlohmann::json::array();
    for (int r = 0; r < 4; ++r) {
      matrix.push_back({c2w(r, 0), c2w(r, 1), c2w(r, 2), c2w(r, 3)});
    }
    frames.push_back({{"file_path", "images/" + ExportedPhotoName(image.name)},
                      {"transform_matrix", matrix},
                      {"colmap_im_id", id},
                      {"fl_x", camera.focal()},
                      {"fl_y", camera.fy()},
                      {"cx", camera.params[Camera::kU0]},
                      {"cy", camera.params[Camera::kV0]},
                      {"w", camera.width},
                      {"h", camera.height},
                      {"k1", camera.params[Camera::kK1]},
                      {"k2", camera.params[Camera::kK2]},
                      {"p1", 0.0},
                      {"p2", 0.0}});
  }
  if (skew_dropped) warn("nerfstudio has no skew parameter: the cameras' skew is dropped");
  // The world frame is the model's own (applied_transform is the identity), so the sparse
  // points and any other varsfm output stay aligned with the cameras.
  return {{"camera_model", "OPENCV"},
          {"frames", frames},
          {"ply_file_path", "sparse_pc.ply"},
          {"applied_transform", {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}}}};
}

NerfstudioExportSummary ExportNerfstudio(const Reconstruction& reconstruction,
                                         const std::filesystem::path& image_dir,
                                         const std::filesystem::path& output) {
  const std::vector<image_t> image_ids = ExportedImageIds(reconstruction, image_dir);
  const nlohmann::json transforms = NerfstudioTransforms(reconstruction);
  WriteNewFolder(output, [&](const std::filesystem::path& dir) {
    for (const image_t id : image_ids) {
      const std::string& name = reconstruction.image(id).name;
      const std::filesystem::path written = dir / "images" / ExportedPhotoName(name);
      std::filesystem::create_directories(written.parent_path());
      // The model's cameras are those of the upright pixels (EXIF orientation applied), which
      // nerfstudio's loader does not apply: a photo stored turned or mirrored is written upright
      // (re-encoded, its EXIF dropped), as is one in a format it does not read; the others are
      // copied as they are.
      const std::vector<uint8_t> bytes = ReadImageFile(image_dir / name);
      if (ExportedPhotoName(name) == name && ExifOrientation(bytes.data(), bytes.size()) == 1)
        WriteBytesAtomically(written, bytes);
      else
        WriteImage(written, DecodeImage(image_dir / name, bytes, ColorMode::kColor));
    }
    WritePly(reconstruction, dir / "sparse_pc.ply");
    WriteJsonAtomically(dir / "transforms.json", transforms);
  });
  return {image_ids.size(), reconstruction.points3D().size()};
}

}  // namespace varsfm
