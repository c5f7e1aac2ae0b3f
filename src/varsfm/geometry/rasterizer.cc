#include "varsfm/geometry/rasterizer.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace varsfm {
namespace {

// Twice the signed area of (a, b, p): positive when p is left of a->b in image coordinates
// (y down), i.e. inside a triangle wound clockwise on screen.
double Edge(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  return (b.x() - a.x()) * (p.y() - a.y()) - (b.y() - a.y()) * (p.x() - a.x());
}

// Top-left rule (as Direct3D / OpenGL): a pixel centre exactly on an edge is inside only for a
// "top" edge (horizontal, the others below it) or a "left" edge, so shared edges are drawn once.
bool IsTopLeft(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d d = b - a;
  return (d.y() == 0 && d.x() < 0) || d.y() > 0;
}

}  // namespace

std::vector<ProjectedVertex> ProjectVertices(const std::vector<Eigen::Vector3d>& vertices,
                                             const Camera& camera, const Rigid3d& cam_from_world,
                                             double scale) {
  std::vector<ProjectedVertex> projected;
  ProjectVertices(vertices, camera, cam_from_world, scale, &projected);
  return projected;
}

void ProjectVertices(const std::vector<Eigen::Vector3d>& vertices, const Camera& camera,
                     const Rigid3d& cam_from_world, double scale,
                     std::vector<ProjectedVertex>* out) {
  std::vector<ProjectedVertex>& projected = *out;
  projected.assign(vertices.size(), ProjectedVertex{});
  const Eigen::Matrix3d R = cam_from_world.R();
  const Eigen::Vector3d& t = cam_from_world.translation;
  // Radial distortion r (1 + k1 r^2 + k2 r^4) folds back on itself beyond the radius where its
  // derivative 1 + 3 k1 r^2 + 5 k2 r^4 vanishes: points far outside the view would land inside
  // it. Only radii up to twice the image corners' (where the model was fitted) are trusted.
  double max_r2 = 0;
  for (const Eigen::Vector2d& corner :
       {Eigen::Vector2d(0, 0), Eigen::Vector2d(camera.width, 0), Eigen::Vector2d(0, camera.height),
        Eigen::Vector2d(camera.width, camera.height)})
    max_r2 = std::max(max_r2, camera.ImageToNormalized(corner).squaredNorm());
  max_r2 *= 4;
  const double k1 = camera.params[Camera::kK1], k2 = camera.params[Camera::kK2];
  for (size_t i = 0; i < vertices.size(); ++i) {
    const Eigen::Vector3d x = R * vertices[i] + t;
    // A vertex (nearly) in the camera's plane would project to infinity: treat it as behind.
    if (x.z() <= 1e-9 * (1 + x.head<2>().norm())) continue;
    if (camera.HasDistortion()) {
      const double r2 = x.head<2>().squaredNorm() / (x.z() * x.z());
      if (r2 > max_r2 || 1 + 3 * k1 * r2 + 5 * k2 * r2 * r2 <= 0) continue;
    }
    projected[i].pixel = camera.Project(x) * scale;
    projected[i].depth = x.z();
  }
}

FaceRaster RasterizeFaces(const std::vector<ProjectedVertex>& projected,
                          const std::vector<Eigen::Vector3i>& faces, int width, int height) {
  FaceRaster raster;
  raster.width = width;
  raster.height = height;
  const size_t n = static_cast<size_t>(width) * height;
  raster.depth.assign(n, std::numeric_limits<float>::infinity());
  raster.face.assign(n, -1);
  for (size_t f = 0; f < faces.size(); ++f) {
    const ProjectedVertex* v[3] = {&projected[faces[f][0]], &projected[faces[f][1]],
                                   &projected[faces[f][2]]};
    if (v[0]->depth <= 0 || v[1]->depth <= 0 || v[2]->depth <= 0) continue;
    double area = Edge(v[0]->pixel, v[1]->pixel, v[2]->pixel);
    if (area < 0) {
      std::swap(v[1], v[2]);
      area = -area;
    }
    if (!(area > 1e-12)) continue;  // degenerate (or NaN)
    const Eigen::Vector2d &p0 = v[0]->pixel, &p1 = v[1]->pixel, &p2 = v[2]->pixel;
    const double min_x = std::min({p0.x(), p1.x(), p2.x()});
    const double max_x = std::max({p0.x(), p1.x(), p2.x()});
    const double min_y = std::min({p0.y(), p1.y(), p2.y()});
    const double max_y = std::max({p0.y(), p1.y(), p2.y()});
    // Pixel x covers [x, x + 1) and is sampled at x + 0.5.
    const int x0 = std::max(0, static_cast<int>(std::ceil(min_x - 0.5)));
    const int x1 = std::min(width - 1, static_cast<int>(std::floor(max_x - 0.5)));
    const int y0 = std::max(0, static_cast<int>(std::ceil(min_y - 0.5)));
    const int y1 = std::min(height - 1, static_cast<int>(std::floor(max_y - 0.5)));
    if (x0 > x1 || y0 > y1) continue;
    const bool tl0 = IsTopLeft(p1, p2), tl1 = IsTopLeft(p2, p0), tl2 = IsTopLeft(p0, p1);
    const double inv_z0 = 1 / v[0]->depth, inv_z1 = 1 / v[1]->depth, inv_z2 = 1 / v[2]->depth;
    const double inv_area = 1 / area;
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const Eigen::Vector2d p(x + 0.5, y + 0.5);
        const double w0 = Edge(p1, p2, p), w1 = Edge(p2, p0, p), w2 = Edge(p0, p1, p);
        if (w0 < 0 || w1 < 0 || w2 < 0) continue;
        if ((w0 == 0 && !tl0) || (w1 == 0 && !tl1) || (w2 == 0 && !tl2)) continue;
        // 1/z is affine in the image of a pinhole camera, z itself is not.
        const double inv_z = (w0 * inv_z0 + w1 * inv_z1 + w2 * inv_z2) * inv_area;
        const float z = static_cast<float>(1 / inv_z);
        const size_t i = static_cast<size_t>(y) * width + x;
        if (z < raster.depth[i]) {
          raster.depth[i] = z;
          raster.face[i] = static_cast<int32_t>(f);
        }
      }
    }
  }
  return raster;
}

bool FaceBarycentrics(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                      const Eigen::Vector2d& ray, Eigen::Vector3d* barycentric) {
  // Solve s d = a + l1 (b - a) + l2 (c - a) for (s, l1, l2), d = (x, y, 1): Cramer's rule.
  const Eigen::Vector3d d = ray.homogeneous();
  const Eigen::Vector3d e1 = b - a, e2 = c - a;
  Eigen::Matrix3d M;
  M << d, -e1, -e2;
  const double det = M.determinant();
  if (std::abs(det) < 1e-300) return false;
  const Eigen::Vector3d sol = M.inverse() * a;
  (*barycentric) << 1 - sol[1] - sol[2], sol[1], sol[2];
  return true;
}

}  // namespace varsfm
