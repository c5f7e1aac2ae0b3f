#include "varsfm/synthetic/rendered_truth.h"

#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "varsfm/synthetic/synthetic_reconstruction.h"

namespace varsfm {

TriangleMesh SurfaceMesh(const std::vector<SurfaceQuad>& quads) {
  TriangleMesh mesh;
  for (const SurfaceQuad& q : quads) {
    const int base = static_cast<int>(mesh.vertices.size());
    mesh.vertices.insert(mesh.vertices.end(),
                         {q.origin, q.origin + q.u, q.origin + q.u + q.v, q.origin + q.v});
    mesh.faces.emplace_back(base, base + 1, base + 2);
    mesh.faces.emplace_back(base, base + 2, base + 3);
  }
  return mesh;
}

double NearestHit(const std::vector<SurfaceQuad>& quads, const Eigen::Vector3d& origin,
                  const Eigen::Vector3d& dir, size_t* quad) {
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < quads.size(); ++i) {
    const SurfaceQuad& q = quads[i];
    const Eigen::Vector3d n = q.u.cross(q.v);
    if (std::abs(n.dot(dir)) < 1e-12) continue;
    const double t = n.dot(q.origin - origin) / n.dot(dir);
    if (t <= 1e-9 || t >= best) continue;
    const Eigen::Vector3d p = origin + t * dir - q.origin;
    const double s = p.dot(q.u) / q.u.squaredNorm(), r = p.dot(q.v) / q.v.squaredNorm();
    if (s < 0 || s > 1 || r < 0 || r > 1) continue;
    best = t;
    if (quad) *quad = i;
  }
  return best;
}

Reconstruction SparseModelFromRenderedScene(const RenderedScene& scene, double pixel_step) {
  Reconstruction rec;
  const int n = static_cast<int>(scene.images.size());
  for (int i = 0; i < n; ++i) AddTrueImage(i, scene.cameras[i], scene.poses[i], &rec);
  for (int i = 0; i < n; i += 2) {
    const Camera& cam = scene.cameras[i];
    const Eigen::Vector3d c = scene.poses[i].Center();
    for (double y = pixel_step / 3; y < cam.height; y += pixel_step)
      for (double x = pixel_step / 3; x < cam.width; x += pixel_step) {
        const Eigen::Vector3d dir =
            scene.poses[i].R().transpose() * cam.ImageToNormalized({x, y}).homogeneous();
        const double t = NearestHit(scene.surface, c, dir);
        if (!std::isfinite(t)) continue;
        const Eigen::Vector3d X = c + t * dir;
        std::vector<TrackElement> track;
        for (int j = 0; j < n; ++j) {
          const Camera& cj = scene.cameras[j];
          const Eigen::Vector3d pc = scene.poses[j] * X;
          if (pc.z() <= 0) continue;
          const Eigen::Vector2d px = cj.Project(pc);
          if (px.x() < 0 || px.y() < 0 || px.x() >= cj.width || px.y() >= cj.height) continue;
          const Eigen::Vector3d centre = scene.poses[j].Center();
          if (NearestHit(scene.surface, centre, X - centre) < 1 - 1e-6) continue;  // occluded
          Image& image = rec.image(static_cast<image_t>(j + 1));
          track.push_back({image.image_id, static_cast<point2D_t>(image.points2D.size())});
          image.points2D.push_back({px});
        }
        if (track.size() >= 2) rec.AddPoint3D(X, track);
      }
  }
  return rec;
}

}  // namespace varsfm
