#pragma once
// Stage 6 of the pipeline: a mesh (OUT/mesh.ply of `mesh`), the sparse model and its photos in;
// a textured model out: OUT/textured/model.obj + model.mtl + model_N.png and OUT/model.glb
// (texture/texture_mapping.h).
#include <filesystem>

#include "varsfm/texture/model_texture.h"
#include "varsfm/util/option_check.h"

namespace varsfm {

struct TextureOptions {
  std::filesystem::path mesh;       // PLY triangle mesh
  std::filesystem::path sparse;     // COLMAP model folder (text or binary)
  std::filesystem::path image_dir;  // the photos, by the model's image names
  std::filesystem::path output;     // OUT: OUT/textured/ and OUT/model.glb are written
  TextureMappingOptions texture;
  int holdout = 0;  // every N-th registered image by name is left out (scene/holdout.h); 0: none

  // Throws OptionError (util/option_check.h) for a bad value; files are checked when the stage
  // runs.
  void Check() const;
};

struct TextureSummary {
  TextureMappingStats stats;
  double seconds = 0;
};

// Throws varsfm::Error (one line) for a missing/empty mesh, a missing model or one without
// registered images, or a missing photo / one whose size differs from its camera.
TextureSummary RunTexture(const TextureOptions& options,
                          OptionsCheck check = OptionsCheck::kByStage);

}  // namespace varsfm
