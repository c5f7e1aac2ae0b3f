#include "varsfm/mesh/mesh_topology.h"
#include "varsfm/io/mesh_ply.h"

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "support/test_data.h"

namespace varsfm {
namespace {

// A tetrahedron: closed, every edge shared by two faces.
TriangleMesh Tetrahedron() {
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  mesh.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return mesh;
}

TEST(TriangleMesh, EdgeTopology) {
  TriangleMesh mesh = Tetrahedron();
  EdgeTopology t = ComputeEdgeTopology(mesh);
  EXPECT_EQ(t.num_edges, 6u);
  EXPECT_EQ(t.boundary_edges, 0u);
  EXPECT_EQ(t.non_manifold_edges, 0u);
  mesh.faces.pop_back();  // open: three boundary edges
  t = ComputeEdgeTopology(mesh);
  EXPECT_EQ(t.boundary_edges, 3u);
  mesh.vertices.emplace_back(1, 1, 1);
  mesh.faces.emplace_back(0, 1, 4);  // edge 0-1 now in three faces
  EXPECT_EQ(ComputeEdgeTopology(mesh).non_manifold_edges, 1u);
}

TEST(TriangleMesh, RemoveUnreferencedVerticesRenumbers) {
  TriangleMesh mesh;
  mesh.vertices = {{9, 9, 9}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.colors = {{1, 1, 1}, {2, 2, 2}, {3, 3, 3}, {4, 4, 4}};
  mesh.faces = {{1, 2, 3}};
  RemoveUnreferencedVertices(&mesh);
  ASSERT_EQ(mesh.vertices.size(), 3u);
  EXPECT_EQ(mesh.faces[0], Eigen::Vector3i(0, 1, 2));
  EXPECT_EQ(mesh.colors[0], (Eigen::Matrix<uint8_t, 3, 1>(2, 2, 2)));
}

TEST(TriangleMesh, WritesBinaryPlyWithFaces) {
  testing::TempDir dir("mesh_ply");
  TriangleMesh mesh = Tetrahedron();
  mesh.colors.assign(4, Eigen::Matrix<uint8_t, 3, 1>(10, 20, 30));
  const auto file = dir.path() / "mesh.ply";
  WriteMeshPly(file, mesh);
  std::ifstream in(file, std::ios::binary);
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string bytes = buffer.str();
  const size_t body = bytes.find("end_header\n") + 11;
  ASSERT_NE(bytes.find("element vertex 4\n"), std::string::npos);
  ASSERT_NE(bytes.find("element face 4\n"), std::string::npos);
  ASSERT_NE(bytes.find("property list uchar int vertex_indices"), std::string::npos);
  // 4 vertices x (3 floats + 3 uchars) + 4 faces x (1 uchar + 3 ints).
  EXPECT_EQ(bytes.size() - body, 4u * 15 + 4u * 13);
  float x1;
  std::memcpy(&x1, bytes.data() + body + 15, 4);  // second vertex's x
  EXPECT_EQ(x1, 1.0f);

  mesh.faces.emplace_back(0, 1, 7);
  EXPECT_ANY_THROW(WriteMeshPly(dir.path() / "bad.ply", mesh));
}

}  // namespace
}  // namespace varsfm
