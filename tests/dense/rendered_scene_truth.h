#pragma once
// Exact truth of RenderSyntheticScene's geometry for dense tests: its faces, ray casting against
// them, and the scene as a sparse model with true cameras and surface points.
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "varsfm/scene/reconstruction.h"
#include "varsfm/synthetic/rendered_scene.h"

namespace varsfm::testing {

// The faces of RenderSyntheticScene's room and boxes (synthetic/rendered_scene.cc, MakeScene):
// origin + s u + t v, s, t in [0, 1].
struct Quad {
  Eigen::Vector3d o, u, v;
};

inline std::vector<Quad> SceneQuads() {
  std::vector<Quad> quads = {{{-2.5, -1.8, 2.0}, {7.0, 0, 0}, {0, 3.0, 0}},
                             {{-2.5, 1.2, -2.0}, {7.0, 0, 0}, {0, 0, 4.0}},
                             {{-2.5, -1.8, -2.0}, {0, 0, 4.0}, {0, 3.0, 0}}};
  const auto box = [&](Eigen::Vector3d c, Eigen::Vector3d half) {
    const Eigen::Vector3d lo = c - half, hi = c + half;
    quads.push_back({lo, {hi.x() - lo.x(), 0, 0}, {0, hi.y() - lo.y(), 0}});
    quads.push_back({lo, {0, 0, hi.z() - lo.z()}, {0, hi.y() - lo.y(), 0}});
    quads.push_back({{hi.x(), lo.y(), lo.z()}, {0, 0, hi.z() - lo.z()}, {0, hi.y() - lo.y(), 0}});
    quads.push_back({lo, {hi.x() - lo.x(), 0, 0}, {0, 0, hi.z() - lo.z()}});
  };
  box({-0.6, 0.7, 0.6}, {0.5, 0.5, 0.5});
  box({0.9, 0.9, 0.1}, {0.35, 0.3, 0.35});
  return quads;
}

// Nearest hit along a ray (t > 0), infinity when none.
inline double Hit(const std::vector<Quad>& quads, const Eigen::Vector3d& o,
                  const Eigen::Vector3d& d, int* which = nullptr) {
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < quads.size(); ++i) {
    const Quad& q = quads[i];
    const Eigen::Vector3d n = q.u.cross(q.v);
    if (std::abs(n.dot(d)) < 1e-12) continue;
    const double t = n.dot(q.o - o) / n.dot(d);
    if (t <= 1e-9 || t >= best) continue;
    const Eigen::Vector3d p = o + t * d - q.o;
    const double s = p.dot(q.u) / q.u.squaredNorm(), r = p.dot(q.v) / q.v.squaredNorm();
    if (s < 0 || s > 1 || r < 0 || r > 1) continue;
    best = t;
    if (which) *which = static_cast<int>(i);
  }
  return best;
}

// Distance from a point to the nearest face plane, and that plane's unit normal.
inline double PlaneDistance(const std::vector<Quad>& quads, const Eigen::Vector3d& x,
                            Eigen::Vector3d* normal) {
  double best = std::numeric_limits<double>::infinity();
  for (const Quad& q : quads) {
    const Eigen::Vector3d n = q.u.cross(q.v).normalized();
    const double d = std::abs(n.dot(x - q.o));
    if (d < best) best = d, *normal = n;
  }
  return best;
}

// The rendered scene as a sparse model: true cameras, and as 3D points the surface points seen
// through a grid of pixels of every image, with their visible observations.
inline Reconstruction SparseModel(const RenderedScene& scene, const std::vector<Quad>& quads) {
  Reconstruction rec;
  const int n = static_cast<int>(scene.images.size());
  for (int i = 0; i < n; ++i) {
    rec.AddCamera(scene.cameras[i]);
    Image image;
    image.image_id = i + 1;
    image.camera_id = scene.cameras[i].camera_id;
    image.name = "image" + std::to_string(i);
    image.cam_from_world = scene.poses[i];
    image.registered = true;
    rec.AddImage(image);
  }
  for (int i = 0; i < n; i += 2) {
    const Camera& cam = scene.cameras[i];
    const Eigen::Vector3d c = scene.poses[i].Center();
    for (double y = 8.5; y < cam.height; y += 24)
      for (double x = 8.5; x < cam.width; x += 24) {
        const Eigen::Vector3d dir =
            scene.poses[i].R().transpose() * cam.ImageToNormalized({x, y}).homogeneous();
        const double t = Hit(quads, c, dir);
        if (!std::isfinite(t)) continue;
        const Eigen::Vector3d X = c + t * dir;
        std::vector<TrackElement> track;
        for (int j = 0; j < n; ++j) {
          const Eigen::Vector3d cj = scene.poses[j].Center();
          const Eigen::Vector3d pc = scene.poses[j] * X;
          if (pc.z() <= 0) continue;
          const Eigen::Vector2d px = scene.cameras[j].Project(pc);
          if (px.x() < 0 || px.y() < 0 || px.x() >= cam.width || px.y() >= cam.height) continue;
          if (Hit(quads, cj, X - cj) < 1 - 1e-6) continue;  // occluded
          Image& image = rec.image(j + 1);
          track.push_back({image.image_id, static_cast<point2D_t>(image.points2D.size())});
          image.points2D.push_back({px});
        }
        if (track.size() >= 2) rec.AddPoint3D(X, track);
      }
  }
  return rec;
}

}  // namespace varsfm::testing
