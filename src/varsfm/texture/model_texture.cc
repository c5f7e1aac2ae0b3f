#include "varsfm/texture/model_texture.h"

#include "varsfm/io/model_photo.h"
#include "varsfm/util/error.h"

namespace varsfm {

std::vector<PosedCamera> RegisteredViews(const Reconstruction& reconstruction,
                                         std::vector<image_t>* image_ids) {
  std::vector<PosedCamera> views;
  image_ids->clear();
  for (const image_t id : reconstruction.RegisteredImageIds()) {
    views.push_back({reconstruction.CameraOf(id), reconstruction.image(id).cam_from_world});
    image_ids->push_back(id);
  }
  return views;
}

TexturedMesh TextureFromModel(const TriangleMesh& mesh, const Reconstruction& reconstruction,
                              const std::filesystem::path& image_dir,
                              const TextureMappingOptions& options, TextureMappingStats* stats) {
  std::vector<image_t> ids;
  const std::vector<PosedCamera> views = RegisteredViews(reconstruction, &ids);
  if (views.empty()) Fail("texture: the sparse model has no registered images to texture from");
  return TextureMesh(
      mesh, views, [&](size_t v) { return ReadModelPhoto(reconstruction, ids[v], image_dir); },
      options, stats);
}

}  // namespace varsfm
