// Decimation to a face budget, on a sphere with exact truth: the budget is kept, the vertices
// stay on the sphere, the faces keep facing out, and a mesh within its budget is left alone.
#include "varsfm/mesh/decimation.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "varsfm/util/option_check.h"

namespace varsfm {
namespace {

// A unit sphere as a latitude-longitude grid: `rings` rings of `segments` vertices between
// the poles, counter-clockwise seen from outside.
TriangleMesh UvSphere(int rings, int segments) {
  TriangleMesh mesh;
  mesh.vertices.push_back({0, 0, 1});
  for (int r = 1; r <= rings; ++r) {
    const double theta = std::numbers::pi * r / (rings + 1);
    for (int s = 0; s < segments; ++s) {
      const double phi = 2 * std::numbers::pi * s / segments;
      mesh.vertices.push_back(
          {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)});
    }
  }
  mesh.vertices.push_back({0, 0, -1});
  const int south = static_cast<int>(mesh.vertices.size()) - 1;
  const auto at = [&](int r, int s) { return 1 + (r - 1) * segments + (s % segments); };
  for (int s = 0; s < segments; ++s) {
    mesh.faces.push_back({0, at(1, s), at(1, s + 1)});
    mesh.faces.push_back({south, at(rings, s + 1), at(rings, s)});
    for (int r = 1; r < rings; ++r) {
      mesh.faces.push_back({at(r, s), at(r + 1, s), at(r + 1, s + 1)});
      mesh.faces.push_back({at(r, s), at(r + 1, s + 1), at(r, s + 1)});
    }
  }
  return mesh;
}

TEST(Decimation, KeepsTheBudgetTheSphereAndTheOrientation) {
  TriangleMesh mesh = UvSphere(60, 120);  // 14,400 faces
  ASSERT_EQ(mesh.faces.size(), 14400u);
  const size_t removed = DecimateMesh({.max_faces = 1500}, &mesh);
  EXPECT_EQ(removed, 14400u - mesh.faces.size());
  EXPECT_LE(mesh.faces.size(), 1500u);
  EXPECT_GE(mesh.faces.size(), 1200u);
  for (const Eigen::Vector3d& v : mesh.vertices) EXPECT_NEAR(v.norm(), 1.0, 0.01);
  for (const Eigen::Vector3i& f : mesh.faces) {
    const Eigen::Vector3d &a = mesh.vertices[f[0]], &b = mesh.vertices[f[1]],
                          &c = mesh.vertices[f[2]];
    EXPECT_GT((b - a).cross(c - a).dot(a + b + c), 0);  // facing away from the centre
  }
}

TEST(Decimation, IsDeterministic) {
  TriangleMesh first = UvSphere(40, 80), second = UvSphere(40, 80);
  DecimateMesh({.max_faces = 800}, &first);
  DecimateMesh({.max_faces = 800}, &second);
  EXPECT_EQ(first.vertices, second.vertices);
  EXPECT_EQ(first.faces, second.faces);
}

TEST(Decimation, LeavesAMeshWithinItsBudgetAlone) {
  const TriangleMesh original = UvSphere(10, 20);
  for (const size_t budget : {size_t{0}, original.faces.size(), size_t{100000}}) {
    TriangleMesh mesh = original;
    EXPECT_EQ(DecimateMesh({.max_faces = budget}, &mesh), 0u);
    EXPECT_EQ(mesh.faces, original.faces);
  }
}

TEST(Decimation, RefusesABudgetBelowATetrahedron) {
  EXPECT_THROW(DecimationOptions{.max_faces = 3}.Check(), OptionError);
  EXPECT_NO_THROW(DecimationOptions{.max_faces = 0}.Check());
  EXPECT_NO_THROW(DecimationOptions{.max_faces = 4}.Check());
}

}  // namespace
}  // namespace varsfm
