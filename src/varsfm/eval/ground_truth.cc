#include "varsfm/eval/ground_truth.h"

#include <cmath>
#include <fstream>

#include <Eigen/SVD>

#include "varsfm/util/error.h"

namespace varsfm {

namespace fs = std::filesystem;

GroundTruthCamera ReadStrechaCamera(const fs::path& file) {
  std::ifstream in(file);
  if (!in) Fail("{}: cannot open", file.string());
  Eigen::Matrix3d K, R;
  Eigen::Vector3d distortion, C;
  double width, height;
  for (int r = 0; r < 3; ++r) in >> K(r, 0) >> K(r, 1) >> K(r, 2);
  in >> distortion.x() >> distortion.y() >> distortion.z();
  for (int r = 0; r < 3; ++r) in >> R(r, 0) >> R(r, 1) >> R(r, 2);
  in >> C.x() >> C.y() >> C.z() >> width >> height;
  if (!in)
    Fail("{}: not a Strecha camera file (expected K, 0 0 0, R, C, width height)", file.string());
  if (K(2, 0) != 0 || K(2, 1) != 0 || K(2, 2) != 1 || K(1, 0) != 0)
    Fail("{}: K is not upper triangular with K(2,2) = 1", file.string());
  // The files hold R to 6-9 digits; 1e-4 catches a transposed or garbled matrix, not rounding.
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-4 ||
      R.determinant() < 0)
    Fail("{}: R is not a rotation", file.string());
  if (!distortion.isZero()) Fail("{}: non-zero distortion row is not supported", file.string());
  // Checked before the conversion to int, undefined beyond its range (or for NaN).
  if (!(width >= 1 && width <= 1e6 && height >= 1 && height <= 1e6))
    Fail("{}: image size {} x {} is not plausible", file.string(), width, height);

  GroundTruthCamera gt;
  gt.name = file.stem().string();  // "0000.jpg.camera" -> "0000.jpg"
  gt.camera.width = static_cast<int>(width);
  gt.camera.height = static_cast<int>(height);
  K(0, 2) += 0.5;  // Strecha's (0, 0) is a pixel centre; varsfm's is a pixel corner
  K(1, 2) += 0.5;
  gt.camera.SetK(K);
  // Project to the nearest rotation so poses are exactly orthonormal despite file rounding.
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Matrix3d world_from_cam = svd.matrixU() * svd.matrixV().transpose();
  gt.cam_from_world = Rigid3d(world_from_cam.transpose(), -world_from_cam.transpose() * C);
  return gt;
}

GroundTruth ReadStrechaGroundTruth(const fs::path& dir) {
  if (!fs::is_directory(dir)) Fail("{}: ground-truth folder does not exist", dir.string());
  GroundTruth gt;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.is_regular_file() && entry.path().extension() == ".camera") {
      GroundTruthCamera camera = ReadStrechaCamera(entry.path());
      gt.cameras.emplace(camera.name, std::move(camera));
    }
  if (gt.cameras.empty()) Fail("{}: no *.camera files", dir.string());
  return gt;
}

}  // namespace varsfm
