#pragma once
// A textured mesh as Wavefront OBJ + MTL + PNG atlas pages (what Blender, MeshLab and most
// tools read): `v x y z`, `vt u v` (OBJ's v axis points up, so v = 1 - v_glTF), one material per
// page (`usemtl page_N`, `map_Kd NAME_N.png`), faces `f v/vt v/vt v/vt` (1-based).
#include <filesystem>
#include <string>

#include "varsfm/scene/textured_mesh.h"

namespace varsfm {

// Writes DIR/NAME.obj, DIR/NAME.mtl and DIR/NAME_N.png. The files appear together (written in a
// temporary folder, then renamed). Throws varsfm::Error.
void WriteTexturedObj(const std::filesystem::path& dir, const TexturedMesh& mesh,
                      const std::string& name = "model");

// Reads an OBJ with its MTL and textures (triangles or polygons fanned into triangles; normals
// ignored). Throws varsfm::Error naming the file that is missing or malformed.
TexturedMesh ReadTexturedObj(const std::filesystem::path& obj_file);

}  // namespace varsfm
