#pragma once
// Export to Bundler v0.3 (Snavely's bundle.out + list.txt), read by PMVS/CMVS, MeshLab and
// older multi-view-stereo tools. Bundler's conventions differ from varsfm's:
//  - camera: P = R X + t with the camera looking down -z and y up, so R_b = D R, t_b = D t with
//    D = diag(1, -1, -1); projection p = -(P.x, P.y) / P.z, then f (1 + k1 |p|^2 + k2 |p|^4) p;
//  - image points relative to the image centre with y up: (u - w/2, h/2 - v) in varsfm pixels;
//  - one focal length and the principal point at the image centre: cameras with aspect != 1,
//    skew or an offset principal point are written anyway, and the log says so (Bundler cannot
//    hold them, so their points reproject off by that offset).
#include <filesystem>

#include "varsfm/scene/reconstruction.h"

namespace varsfm {

// Writes `bundle_file` (bundle.out) and `list_file` (list.txt), each atomically (a temporary file
// beside it, renamed onto it once complete: util/atomic_file.h). Every image is listed, in id
// order; an unregistered image gets Bundler's empty camera (all zeros). The keypoint index in
// the view lists is the 2D point index in the image. Throws varsfm::Error.
void WriteBundler(const Reconstruction& reconstruction, const std::filesystem::path& bundle_file,
                  const std::filesystem::path& list_file);

}  // namespace varsfm
