// Hole filling on flat grids, where the filled surface is known exactly.
#include "varsfm/mesh/hole_filling.h"

#include <array>
#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "varsfm/mesh/mesh_topology.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

// An n x n grid of unit squares in the plane z = 0, two counter-clockwise triangles (seen from
// +z) per square, without the squares whose lower-left corner (i, j) `removed` says.
template <typename Removed>
TriangleMesh Grid(int n, Removed removed) {
  TriangleMesh mesh;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) mesh.vertices.emplace_back(i, j, 0);
  const auto id = [&](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if (removed(i, j)) continue;
      mesh.faces.emplace_back(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      mesh.faces.emplace_back(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  return mesh;
}

double ZOfNormal(const TriangleMesh& mesh, const Eigen::Vector3i& f) {
  return (mesh.vertices[f[1]] - mesh.vertices[f[0]])
      .cross(mesh.vertices[f[2]] - mesh.vertices[f[0]])
      .z();
}

// FillSmallHoles with max_edges: its loops, filled loops and added faces.
using Counts = std::array<size_t, 3>;
Counts Fill(int max_edges, TriangleMesh* mesh) {
  HoleFillingOptions options;
  options.max_edges = max_edges;
  const HoleFillingStats stats = FillSmallHoles(options, mesh);
  return {stats.loops, stats.filled_loops, stats.added_faces};
}

// The area of the faces from `first` on; -1 when one of them is not counter-clockwise from +z
// like the grid.
double AreaFacingUp(const TriangleMesh& mesh, size_t first) {
  double area = 0;
  for (size_t f = first; f < mesh.faces.size(); ++f) {
    const double z = ZOfNormal(mesh, mesh.faces[f]);
    if (!(z > 0)) return -1;
    area += z / 2;
  }
  return area;
}

TEST(HoleFilling, ClosesASmallHoleFlatAndFacingLikeItsSurrounding) {
  // A 2 x 3 block of squares missing: a loop of 10 unit edges; the grid's outer loop has 80.
  TriangleMesh mesh = Grid(20, [](int i, int j) { return i >= 8 && i < 10 && j >= 5 && j < 8; });
  const size_t before = mesh.faces.size();
  // A polygon of 10 vertices takes 8 triangles; they cover the 6 missing squares exactly.
  EXPECT_EQ(Fill(12, &mesh), (Counts{2, 1, 8}));  // loops, filled, faces added
  ASSERT_EQ(mesh.faces.size(), before + 8);
  EXPECT_NEAR(AreaFacingUp(mesh, before), 6.0, 1e-12);
  const EdgeTopology topology = ComputeEdgeTopology(mesh);
  EXPECT_EQ(topology.boundary_edges, 80u);  // only the outer edge is left
  EXPECT_EQ(topology.non_manifold_edges, 0u);
}

TEST(HoleFilling, LeavesLoopsAboveTheLimitAndTheOuterEdgeOpen) {
  // A 4 x 4 hole (16 edges) above a limit of 12; a 3 x 3 grid's outer edge (12 edges) under it.
  TriangleMesh big = Grid(20, [](int i, int j) { return i >= 4 && i < 8 && j >= 4 && j < 8; });
  TriangleMesh small = Grid(3, [](int, int) { return false; });
  HoleFillingOptions options;
  options.max_edges = 12;
  for (TriangleMesh* mesh : {&big, &small}) {
    const size_t faces = mesh->faces.size();
    const HoleFillingStats stats = FillSmallHoles(options, mesh);
    EXPECT_EQ(stats.filled_loops, 0u);
    EXPECT_EQ(mesh->faces.size(), faces);
  }
  EXPECT_EQ(FillSmallHoles(options, &small).loops, 1u);
  // With 16 allowed, the hole closes (4 x 4 squares = 16 area) and the outer edge still not.
  options.max_edges = 16;
  const HoleFillingStats stats = FillSmallHoles(options, &big);
  EXPECT_EQ(stats.filled_loops, 1u);
  EXPECT_EQ(stats.added_faces, 14u);
  EXPECT_EQ(ComputeEdgeTopology(big).boundary_edges, 80u);
}

TEST(HoleFilling, LongEdgesCountAgainstTheLimit) {
  // The same 10-edge loop on a grid stretched 3x along x around the hole's columns: its
  // perimeter is more than 12 median edges though it has 10 edges, so it stays open.
  TriangleMesh mesh = Grid(20, [](int i, int j) { return i >= 8 && i < 10 && j >= 5 && j < 8; });
  for (Eigen::Vector3d& v : mesh.vertices)
    if (v.x() >= 8 && v.x() <= 10 && v.y() >= 5 && v.y() <= 8) v.y() = 5 + 4 * (v.y() - 5);
  HoleFillingOptions options;
  options.max_edges = 12;
  EXPECT_EQ(FillSmallHoles(options, &mesh).filled_loops, 0u);
}

TEST(HoleFilling, SplitsHolesThatMeetAtAVertex) {
  // Two missing squares touching at the corner (6, 6): that vertex has two boundary edges out
  // and two in; the walk must close two 4-edge loops there, each filled with 2 triangles.
  TriangleMesh mesh =
      Grid(12, [](int i, int j) { return (i == 5 && j == 5) || (i == 6 && j == 6); });
  const size_t before = mesh.faces.size();
  EXPECT_EQ(Fill(4, &mesh), (Counts{3, 2, 4}));
  EXPECT_NEAR(AreaFacingUp(mesh, before), 2.0, 1e-12);
  const EdgeTopology topology = ComputeEdgeTopology(mesh);
  EXPECT_EQ(topology.boundary_edges, 48u);
  EXPECT_EQ(topology.non_manifold_edges, 0u);
}

TEST(HoleFilling, ClosesAHoleWhoseRimCarriesAFlap) {
  // The 2 x 3 hole of the first test, with a flap of two faces standing on its rim edge
  // (8, 5) - (9, 5), as the cut leaves one where a fourth face round an edge was removed as long:
  // that edge has three faces, two of them running along it the same way, and the hole's
  // boundary passes through it. Its loop must still close and be filled.
  TriangleMesh mesh = Grid(20, [](int i, int j) { return i >= 8 && i < 10 && j >= 5 && j < 8; });
  const int a = 5 * 21 + 8, b = 5 * 21 + 9;  // (8, 5) and (9, 5)
  const int p = static_cast<int>(mesh.vertices.size());
  mesh.vertices.emplace_back(8.5, 4.8, 1.0);
  mesh.vertices.emplace_back(8.5, 5.2, 1.0);
  mesh.faces.emplace_back(b, a, p);      // along the rim face below, which runs b -> a
  mesh.faces.emplace_back(a, b, p + 1);  // against it
  ASSERT_EQ(ComputeEdgeTopology(mesh).non_manifold_edges, 1u);
  const size_t before = mesh.faces.size();
  const Counts counts = Fill(12, &mesh);
  EXPECT_GE(counts[1], 1u);  // the hole (the flap's own edges make a loop of four)
  // The faces added in the plane z = 0 cover the 6 missing squares, facing up.
  double flat_area = 0;
  for (size_t f = before; f < mesh.faces.size(); ++f) {
    const Eigen::Vector3i& face = mesh.faces[f];
    if (mesh.vertices[face[0]].z() != 0 || mesh.vertices[face[1]].z() != 0 ||
        mesh.vertices[face[2]].z() != 0)
      continue;
    EXPECT_GT(ZOfNormal(mesh, face), 0);
    flat_area += ZOfNormal(mesh, face) / 2;
  }
  EXPECT_NEAR(flat_area, 6.0, 1e-12);
}

// The mean distance, along z, of the centroids of the faces from `first` on from the surface
// z = height(x, y).
template <typename Height>
double MeanCentroidHeightError(const TriangleMesh& mesh, size_t first, Height height) {
  double sum = 0;
  for (size_t f = first; f < mesh.faces.size(); ++f) {
    const Eigen::Vector3i& face = mesh.faces[f];
    const Eigen::Vector3d c =
        (mesh.vertices[face[0]] + mesh.vertices[face[1]] + mesh.vertices[face[2]]) / 3;
    sum += std::abs(c.z() - height(c.x(), c.y()));
  }
  return sum / static_cast<double>(mesh.faces.size() - first);
}

TEST(HoleFilling, RefinedAndFairedPatchFollowsACurvedSurface) {
  // A bowl z = 0.05 ((x - 10)^2 + (y - 10)^2) sampled on the grid, with a 6 x 6 hole at its
  // bottom. Triangles over the loop's own vertices span it flat at the rim's height (z 0.45 to
  // 0.9), the bowl's bottom being at 0. The bowl is biharmonic (its Laplacian is constant), so
  // thin-plate fairing with the surrounding faces held fixed reproduces it up to the
  // discretisation.
  const auto height = [](double x, double y) {
    return 0.05 * ((x - 10) * (x - 10) + (y - 10) * (y - 10));
  };
  const auto bowl = [&] {
    TriangleMesh mesh = Grid(20, [](int i, int j) { return i >= 7 && i < 13 && j >= 7 && j < 13; });
    for (Eigen::Vector3d& v : mesh.vertices) v.z() = height(v.x(), v.y());
    return mesh;
  };
  HoleFillingOptions options;
  options.max_edges = 30;
  TriangleMesh flat = bowl(), faired = bowl();
  const size_t before = flat.faces.size(), vertices = flat.vertices.size();
  const HoleFillingStats flat_stats = FillSmallHoles(options, &flat);
  options.refine_and_fair = true;
  const HoleFillingStats faired_stats = FillSmallHoles(options, &faired);
  EXPECT_EQ(flat_stats.filled_loops, 1u);
  EXPECT_EQ(flat_stats.added_vertices, 0u);
  EXPECT_EQ(flat.vertices.size(), vertices);
  EXPECT_EQ(faired_stats.filled_loops, 1u);
  EXPECT_EQ(faired_stats.faired_loops, 1u);
  // Refined towards the grid's density (the hole holds 25 grid vertices inside it).
  EXPECT_GT(faired_stats.added_vertices, 10u);
  EXPECT_EQ(faired.vertices.size(), vertices + faired_stats.added_vertices);
  EXPECT_EQ(faired_stats.added_faces, faired.faces.size() - before);
  EXPECT_GT(faired_stats.added_faces, 2 * faired_stats.added_vertices);

  // The new vertices lie on the bowl (within 0.05, its rim being 0.45-0.9 above its bottom); the
  // faces between them then stay closer to it than the flat patch's (their centroids sag by the
  // chord error of faces about a grid square wide).
  for (size_t i = vertices; i < faired.vertices.size(); ++i) {
    const Eigen::Vector3d& v = faired.vertices[i];
    EXPECT_NEAR(v.z(), height(v.x(), v.y()), 0.05) << "new vertex " << i;
  }
  const double flat_error = MeanCentroidHeightError(flat, before, height);
  const double faired_error = MeanCentroidHeightError(faired, before, height);
  EXPECT_GT(flat_error, 0.1);
  EXPECT_LT(faired_error, 0.4 * flat_error);
  // The patch closes the hole, facing up like the bowl, and covers it exactly once.
  EXPECT_NEAR(AreaFacingUp(faired, before), 36.0, 1e-9);
  const EdgeTopology topology = ComputeEdgeTopology(faired);
  EXPECT_EQ(topology.boundary_edges, 80u);
  EXPECT_EQ(topology.non_manifold_edges, 0u);
}

TEST(HoleFilling, NegativeLimitIsAnOptionError) {
  HoleFillingOptions options;
  options.max_edges = -1;
  EXPECT_THROW(options.Check(), Error);
}

}  // namespace
}  // namespace varsfm
