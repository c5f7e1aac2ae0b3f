#pragma once
// A textured mesh as binary glTF 2.0 (.glb; Khronos glTF 2.0 specification): one buffer holding
// positions, texture coordinates, per-page triangle indices and the atlas pages as embedded PNG
// images; one primitive and one material per page. Materials are flagged
// KHR_materials_unlit because the atlas holds photographed (already lit) colour. Vertices are
// written in the sparse model's coordinates; the scene's node turns them half a turn about x
// (vision y-down to glTF y-up).
#include <filesystem>

#include "varsfm/scene/textured_mesh.h"

namespace varsfm {

// Written through a temporary file and a rename. Throws varsfm::Error.
void WriteGlb(const std::filesystem::path& file, const TexturedMesh& mesh);

}  // namespace varsfm
