#pragma once
// The geometry of the rendered synthetic scene (synthetic/rendered_scene.cc: MakeScene) as a
// triangle mesh: every textured rectangle cut into a grid of small triangles. The rectangles are
// repeated here because the generator keeps them private; if the scene changes, the texture
// tests' PSNR bounds fail loudly rather than silently.
#include <cmath>
#include <vector>

#include <Eigen/Core>

#include "varsfm/scene/triangle_mesh.h"

namespace varsfm::testing {

inline void AddGridQuad(const Eigen::Vector3d& o, const Eigen::Vector3d& u,
                        const Eigen::Vector3d& v, double cell, TriangleMesh* mesh) {
  const int nu = std::max(1, static_cast<int>(std::ceil(u.norm() / cell)));
  const int nv = std::max(1, static_cast<int>(std::ceil(v.norm() / cell)));
  const int base = static_cast<int>(mesh->vertices.size());
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i <= nu; ++i)
      mesh->vertices.push_back(o + u * (static_cast<double>(i) / nu) +
                               v * (static_cast<double>(j) / nv));
  const auto id = [&](int i, int j) { return base + j * (nu + 1) + i; };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      mesh->faces.emplace_back(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      mesh->faces.emplace_back(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
}

// Room corner (back wall, floor, left wall) and two boxes' front, left, right and top faces.
inline TriangleMesh SyntheticSceneMesh(double cell = 0.1) {
  TriangleMesh mesh;
  AddGridQuad({-2.5, -1.8, 2.0}, {7.0, 0, 0}, {0, 3.0, 0}, cell, &mesh);
  AddGridQuad({-2.5, 1.2, -2.0}, {7.0, 0, 0}, {0, 0, 4.0}, cell, &mesh);
  AddGridQuad({-2.5, -1.8, -2.0}, {0, 0, 4.0}, {0, 3.0, 0}, cell, &mesh);
  const auto box = [&](Eigen::Vector3d c, Eigen::Vector3d half) {
    const Eigen::Vector3d lo = c - half, hi = c + half;
    AddGridQuad(lo, {hi.x() - lo.x(), 0, 0}, {0, hi.y() - lo.y(), 0}, cell, &mesh);
    AddGridQuad(lo, {0, 0, hi.z() - lo.z()}, {0, hi.y() - lo.y(), 0}, cell, &mesh);
    AddGridQuad({hi.x(), lo.y(), lo.z()}, {0, 0, hi.z() - lo.z()}, {0, hi.y() - lo.y(), 0}, cell,
                &mesh);
    AddGridQuad(lo, {hi.x() - lo.x(), 0, 0}, {0, 0, hi.z() - lo.z()}, cell, &mesh);
  };
  box({-0.6, 0.7, 0.6}, {0.5, 0.5, 0.5});
  box({0.9, 0.9, 0.1}, {0.35, 0.3, 0.35});
  return mesh;
}

}  // namespace varsfm::testing
