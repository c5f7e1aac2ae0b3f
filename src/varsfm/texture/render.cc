#include "varsfm/texture/render.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>

#include "varsfm/geometry/rasterizer.h"
#include "varsfm/texture/atlas_sample.h"
#include "varsfm/texture/ssim.h"
#include "varsfm/util/error.h"

namespace varsfm {

Rendering RenderTexturedMesh(const TexturedMesh& mesh, const Camera& camera,
                             const Rigid3d& cam_from_world) {
  const std::vector<ProjectedVertex> projected =
      ProjectVertices(mesh.vertices, camera, cam_from_world);
  const FaceRaster raster = RasterizeFaces(projected, mesh.faces, camera.width, camera.height);
  std::vector<Eigen::Vector3d> in_camera(mesh.vertices.size());
  for (size_t i = 0; i < mesh.vertices.size(); ++i)
    in_camera[i] = cam_from_world * mesh.vertices[i];

  Rendering out;
  out.image = cv::Mat(camera.height, camera.width, CV_8UC3, cv::Scalar::all(0));
  out.mask = cv::Mat(camera.height, camera.width, CV_8UC1, cv::Scalar::all(0));
  tbb::parallel_for(0, camera.height, [&](int y) {
    cv::Vec3b* row = out.image.ptr<cv::Vec3b>(y);
    uchar* mask_row = out.mask.ptr<uchar>(y);
    for (int x = 0; x < camera.width; ++x) {
      const int32_t f = raster.FaceAt(x, y);
      if (f < 0) continue;
      const Eigen::Vector3i& face = mesh.faces[f];
      const Eigen::Vector2d ray = camera.ImageToNormalized(Eigen::Vector2d(x + 0.5, y + 0.5));
      Eigen::Vector3d l;
      if (!FaceBarycentrics(in_camera[face[0]], in_camera[face[1]], in_camera[face[2]], ray, &l))
        continue;
      // Pixels sampled at a face's edge can fall just outside it: stay within the face's chart.
      l = l.cwiseMax(0.0);
      l /= std::max(l.sum(), 1e-12);
      const Eigen::Vector3i& tc = mesh.face_texcoords[f];
      const Eigen::Vector2d uv = l[0] * mesh.texcoords[tc[0]].cast<double>() +
                                 l[1] * mesh.texcoords[tc[1]].cast<double>() +
                                 l[2] * mesh.texcoords[tc[2]].cast<double>();
      const cv::Mat& page = mesh.pages[mesh.face_page[f]];
      const cv::Vec3f c = SampleAtlas(page, uv.x() * page.cols, uv.y() * page.rows);
      row[x] = cv::Vec3b(cv::saturate_cast<uchar>(c[0]), cv::saturate_cast<uchar>(c[1]),
                         cv::saturate_cast<uchar>(c[2]));
      mask_row[x] = 255;
    }
  });
  return out;
}

cv::Mat RenderShadedMesh(const std::vector<Eigen::Vector3d>& vertices,
                         const std::vector<Eigen::Vector3i>& faces, const Camera& camera,
                         const Rigid3d& cam_from_world) {
  const FaceRaster raster = RasterizeFaces(ProjectVertices(vertices, camera, cam_from_world), faces,
                                           camera.width, camera.height);
  std::vector<Eigen::Vector3d> normals(faces.size(), Eigen::Vector3d::Zero());
  for (size_t f = 0; f < faces.size(); ++f) {
    const Eigen::Vector3d a = cam_from_world * vertices[faces[f][0]];
    normals[f] = (cam_from_world * vertices[faces[f][1]] - a)
                     .cross(cam_from_world * vertices[faces[f][2]] - a)
                     .normalized();
  }
  cv::Mat image(camera.height, camera.width, CV_8UC3, cv::Scalar::all(0));
  tbb::parallel_for(0, camera.height, [&](int y) {
    cv::Vec3b* row = image.ptr<cv::Vec3b>(y);
    for (int x = 0; x < camera.width; ++x) {
      const int32_t f = raster.FaceAt(x, y);
      if (f < 0) continue;
      const Eigen::Vector3d ray =
          camera.ImageToNormalized(Eigen::Vector2d(x + 0.5, y + 0.5)).homogeneous().normalized();
      const double shade = std::abs(normals[f].dot(ray));
      // A floor of 40 keeps faces seen edge-on distinct from the empty background.
      row[x] = cv::Vec3b::all(cv::saturate_cast<uchar>(40 + 215 * shade));
    }
  });
  return image;
}

PhotometricScore ComparePhotometric(const Rendering& rendering, const cv::Mat& photo) {
  if (photo.size() != rendering.image.size() || photo.type() != CV_8UC3)
    Fail("photometric comparison: photo is {}x{} but the rendering {}x{}", photo.cols, photo.rows,
         rendering.image.cols, rendering.image.rows);
  PhotometricScore score;
  double sum_sq = 0;
  // Per channel: sums of rendering x photo, rendering^2 and photo^2, whose least-squares gain
  // g = sum(rp) / sum(r^2) leaves sum(p^2) - sum(rp)^2 / sum(r^2) of squared error.
  double rp[3] = {0, 0, 0}, rr[3] = {0, 0, 0}, pp[3] = {0, 0, 0};
  for (int y = 0; y < photo.rows; ++y) {
    const cv::Vec3b* a = rendering.image.ptr<cv::Vec3b>(y);
    const cv::Vec3b* b = photo.ptr<cv::Vec3b>(y);
    const uchar* m = rendering.mask.ptr<uchar>(y);
    for (int x = 0; x < photo.cols; ++x) {
      if (!m[x]) continue;
      ++score.covered_pixels;
      for (int c = 0; c < 3; ++c) {
        const double r = a[x][c], p = b[x][c], d = r - p;
        sum_sq += d * d;
        rp[c] += r * p;
        rr[c] += r * r;
        pp[c] += p * p;
      }
    }
  }
  score.coverage = static_cast<double>(score.covered_pixels) / (photo.rows * photo.cols);
  if (score.covered_pixels == 0) return score;
  score.ssim = MaskedSsim(rendering.image, photo, rendering.mask);
  const auto psnr = [&](double squared_error) {
    const double mse = std::max(0.0, squared_error) / (3.0 * score.covered_pixels);
    return mse > 0 ? 10 * std::log10(255.0 * 255.0 / mse) : std::numeric_limits<double>::infinity();
  };
  score.psnr_db = psnr(sum_sq);
  double exposure_sq = 0;
  for (int c = 0; c < 3; ++c) exposure_sq += rr[c] > 0 ? pp[c] - rp[c] * rp[c] / rr[c] : pp[c];
  // Rounding can leave the exact fit a hair below zero, or above the plain error.
  score.psnr_exposure_db = std::max(score.psnr_db, psnr(exposure_sq));
  return score;
}

}  // namespace varsfm
