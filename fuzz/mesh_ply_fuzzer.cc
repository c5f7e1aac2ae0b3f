// The triangle-mesh PLY reader (texture/mesh_reader.cc on io/ply_format.cc): the meshes
// `varsfm texture` and `varsfm render` take, from varsfm or MeshLab, Open3D, CGAL.
#include "fuzz_support.h"
#include "varsfm/io/mesh_ply.h"
#include "varsfm/util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto file = varsfm::fuzz::ScratchDir() / "mesh.ply";
  varsfm::fuzz::WriteBytes(file, data, size);
  try {
    varsfm::ReadMeshPly(file);
  } catch (const varsfm::Error&) {
  }
  return 0;
}
