#pragma once
// Texturing a mesh from a sparse model's registered images and their photos on disk: the glue
// between a Reconstruction and texture_mapping.h, shared by `varsfm texture` and the renderer's
// evaluation.
#include <filesystem>
#include <vector>

#include <opencv2/core.hpp>

#include "varsfm/scene/reconstruction.h"
#include "varsfm/scene/triangle_mesh.h"
#include "varsfm/texture/texture_mapping.h"

namespace varsfm {

// The registered images of a model as texture views, in image-id order (ids in `image_ids`).
std::vector<PosedCamera> RegisteredViews(const Reconstruction& reconstruction,
                                         std::vector<image_t>* image_ids);

// Throws varsfm::Error (one line) for a model without registered images, an empty mesh, or a
// missing / wrongly sized photo.
TexturedMesh TextureFromModel(const TriangleMesh& mesh, const Reconstruction& reconstruction,
                              const std::filesystem::path& image_dir,
                              const TextureMappingOptions& options = {},
                              TextureMappingStats* stats = nullptr);

}  // namespace varsfm
