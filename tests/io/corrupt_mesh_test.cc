// Mesh files that crashed the readers (found by fuzz/obj_fuzzer.cc's smoke run) or hit undefined
// behaviour or uninitialised values (found by review): each is now one varsfm::Error.
#include <gtest/gtest.h>

#include <fstream>
#include <limits>
#include <string>

#include "support/test_data.h"
#include "varsfm/io/mesh_ply.h"
#include "varsfm/io/obj_io.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

using testing::TempDir;

TEST(CorruptObj, MaterialWithoutATextureFileName) {
  TempDir tmp("corrupt_obj");
  // `map_Kd` with nothing after it names the model's folder: reading that as an image threw
  // std::ios_base::failure out of the reader.
  std::ofstream(tmp.path() / "model.mtl") << "newmtl a\nmap_Kd \n";
  std::ofstream(tmp.path() / "model.obj") << "mtllib model.mtl\nv 0 0 0\nusemtl a\n";
  EXPECT_THROW(ReadTexturedObj(tmp.path() / "model.obj"), Error);
}

TEST(CorruptObj, MalformedVertex) {
  TempDir tmp("corrupt_obj");
  // y and z were left uninitialised and the vertex kept.
  std::ofstream(tmp.path() / "model.obj") << "v 1 x 2\nvt 0 0\n";
  try {
    ReadTexturedObj(tmp.path() / "model.obj");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("model.obj:1: malformed vertex"), std::string::npos)
        << e.what();
  }
}

TEST(CorruptMeshPly, FaceIndexBeyondInt) {
  TempDir tmp("corrupt_mesh_ply");
  // A double index of 1e10 (or NaN) was converted to int: undefined behaviour.
  for (const char* index : {"1e10", "-3e9", "2147483647"}) {
    std::ofstream(tmp.path() / "m.ply")
        << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
           "property float z\nelement face 1\nproperty list uchar double vertex_indices\n"
           "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 "
        << index << "\n";
    EXPECT_THROW(ReadMeshPly(tmp.path() / "m.ply"), Error) << index;
  }
}

// A mesh with a NaN or infinite vertex was textured, exit 0, into an OBJ of `v nan ...` lines.
TEST(CorruptMeshPly, NonFiniteVertexNamesTheFileAndVertex) {
  TempDir tmp("corrupt_mesh_ply");
  for (const double bad :
       {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    TriangleMesh mesh;
    mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, bad}, {0, 0, 1}};
    mesh.faces = {{0, 1, 2}, {0, 1, 3}};
    const auto file = tmp.path() / "mesh.ply";
    WriteMeshPly(file, mesh);
    try {
      ReadMeshPly(file);
      ADD_FAILURE() << "no error for " << bad;
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()), file.string() + " has non-finite coordinates (vertex 2)");
    }
  }
}

}  // namespace
}  // namespace varsfm
