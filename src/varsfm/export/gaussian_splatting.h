#pragma once
// Export for 3D Gaussian Splatting (Kerbl et al. 2023) and the trainers that share its loader:
// undistorted photos in DIR/images and a COLMAP model with PINHOLE cameras in DIR/sparse/0 — the
// layout `colmap image_undistorter` produces and 3DGS' `readColmapSceneInfo` reads. Every
// camera keeps its own focal length: a zooming capture stays a zooming capture.
#include <filesystem>

#include "varsfm/scene/reconstruction.h"

namespace varsfm {

struct GaussianSplattingExportSummary {
  size_t num_images = 0;
  size_t num_points = 0;
  // Exported cameras whose principal point lies more than kOffCentrePrincipalPoint x the larger
  // side from the image centre (photos cropped off-centre). 3DGS' reference loader takes a
  // camera's field of view from its focal length and size and ignores cx, cy, so it misplaces
  // these photos; trainers that read cx, cy (gsplat, nerfstudio's splatfacto) do not.
  size_t num_off_centre = 0;
};

inline constexpr double kOffCentrePrincipalPoint = 0.05;

// The model with every camera replaced by its undistorted pinhole camera
// (undistortion.h) and every 2D observation moved to where it lies in the undistorted image.
Reconstruction UndistortReconstruction(const Reconstruction& reconstruction);

// Writes DIR/images/<name> (every registered image, undistorted, in its own file format) and
// DIR/sparse/0/{cameras,images,points3D}.bin (PINHOLE cameras). `output` must not exist or be
// empty; it appears complete or not at all. Throws varsfm::Error (one line) for a missing photo,
// a photo whose size differs from its camera, or an unwritable output.
GaussianSplattingExportSummary ExportGaussianSplatting(const Reconstruction& reconstruction,
                                                       const std::filesystem::path& image_dir,
                                                       const std::filesystem::path& output);

}  // namespace varsfm
