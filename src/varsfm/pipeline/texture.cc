#include "varsfm/pipeline/texture.h"

#include <algorithm>

#include "varsfm/io/mesh_ply.h"
#include "varsfm/io/obj_io.h"
#include "varsfm/pipeline/output_folder.h"
#include "varsfm/pipeline/scratch_choice.h"
#include "varsfm/pipeline/stage_model.h"
#include "varsfm/scene/holdout.h"
#include "varsfm/texture/face_observations.h"
#include "varsfm/texture/gltf_writer.h"
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"
#include "varsfm/util/path_lock.h"
#include "varsfm/util/timer.h"

namespace varsfm {

void TextureOptions::Check() const {
  texture.Check();
  CheckHoldout(holdout);
}

TextureSummary RunTexture(const TextureOptions& options, OptionsCheck check) {
  if (check == OptionsCheck::kByStage) options.Check();
  OutputFolderLock output_lock(options.output);
  Timer timer;
  const TriangleMesh mesh = ReadMeshPly(options.mesh);
  const Reconstruction rec =
      ReadStageModel("texture", options.sparse, options.image_dir, options.holdout, 1);

  TextureSummary result;
  TextureMappingOptions texture = options.texture;
  FaceObservationOptions& observation = texture.selection.observation;
  observation.scratch_folder = ScratchFolderFor(
      options.output,
      ViewBytes(rec, observation.max_raster_size, FaceObservationOptions::kSmallPhotoBytesPerPixel),
      "texture: the views' small photos");
  const TexturedMesh textured =
      TextureFromModel(mesh, rec, options.image_dir, texture, &result.stats);
  if (result.stats.num_textured_faces == 0)
    Fail(
        "texture: no face of {} ({} faces) is seen by a registered photo within the texture "
        "settings: nothing to texture",
        options.mesh.string(), result.stats.num_faces);
  output_lock.CreateAndLock();
  RemoveOutputsAfter(options.output, ChainStage::kTexture);
  WriteOutputsTogether(options.output, ChainStage::kTexture, [&] {
    WriteTexturedObj(options.output / "textured", textured, "model");
    WriteGlb(options.output / "model.glb", textured);
  });
  result.seconds = timer.Seconds();
  const TextureMappingStats& s = result.stats;
  info(
      "texture: {} of {} faces textured, the mesh covers {:.1f} % of the photos, {} views of "
      "faces rejected as inconsistent, {} charts, {} atlas page(s) ({:.1f} Mpx, {:.0f} % inside "
      "faces) in {:.1f} s (selection {:.1f}, levelling {:.1f}, atlas {:.1f}) -> "
      "{}/textured/model.obj, model.glb",
      s.num_textured_faces, s.num_faces, 100 * s.mean_coverage, s.num_rejected_observations,
      s.num_charts, s.num_pages, s.atlas_pixels / 1e6,
      100 * s.face_texels / std::max<size_t>(1, s.atlas_pixels), result.seconds,
      s.seconds_selection, s.seconds_levelling, s.seconds_atlas, options.output.string());
  return result;
}

}  // namespace varsfm
