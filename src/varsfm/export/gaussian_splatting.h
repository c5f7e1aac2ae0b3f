#pragma once
// Export for 3D Gaussian Splatting (Kerbl et al. 2023) and the trainers that share its loader:
// undistorted photos in DIR/images and a COLMAP model with PINHOLE cameras in DIR/sparse/0 — the
// layout `colmap image_undistorter` produces and 3DGS' `readColmapSceneInfo` reads. Every
// camera keeps its own focal length: a zooming capture stays a zooming capture. 3DGS' reference
// loader takes a camera's field of view from its focal length and size and ignores cx, cy (a
// symmetric frustum), so by default each photo is cut around its principal point, which then
// lies at the image centre exactly (undistortion.h, PrincipalPointPlacement::kCentred).
#include <filesystem>

#include "varsfm/export/undistortion.h"
#include "varsfm/scene/reconstruction.h"

namespace varsfm {

struct GaussianSplattingExportSummary {
  size_t num_images = 0;
  size_t num_points = 0;
  size_t num_centred = 0;  // exported cameras whose principal point was moved to the centre
  // Exported cameras whose principal point lies more than kOffCentrePrincipalPoint x the larger
  // side from the image centre: kept where it is on request, or because centring would keep
  // less than kMinCentredArea of the photo (one cropped far off-centre). 3DGS' reference loader
  // misplaces these photos; trainers that read cx, cy (gsplat, nerfstudio's splatfacto) do not.
  size_t num_off_centre = 0;
};

inline constexpr double kOffCentrePrincipalPoint = 0.05;
inline constexpr double kMinCentredArea = 0.5;

// The pinhole camera a photo is exported with (undistortion.h): with kCentred, centred unless
// that keeps less than kMinCentredArea of the area the principal point's own place keeps, or
// fails; then kept.
Camera ExportedPinholeCamera(const Camera& camera, PrincipalPointPlacement placement);

// The model with every camera replaced by its exported pinhole camera and every 2D observation
// moved to where it lies in the undistorted image.
Reconstruction UndistortReconstruction(const Reconstruction& reconstruction,
                                       PrincipalPointPlacement placement);

// Writes DIR/images/<name> (every registered image, undistorted, in its own file format) and
// DIR/sparse/0/{cameras,images,points3D}.bin (PINHOLE cameras). `output` must not exist or be
// empty; it appears complete or not at all. Throws varsfm::Error (one line) for a missing photo,
// a photo whose size differs from its camera, or an unwritable output.
GaussianSplattingExportSummary ExportGaussianSplatting(
    const Reconstruction& reconstruction, const std::filesystem::path& image_dir,
    const std::filesystem::path& output,
    PrincipalPointPlacement placement = PrincipalPointPlacement::kCentred);

}  // namespace varsfm
