#pragma once
// Stage 4 of the pipeline: a sparse model and its photos in, a dense coloured point cloud with
// normals out (OUT/dense.ply, and OUT/dense.ply.vis: which images see each point), by match
// propagation and/or PatchMatch depth maps (dense/densify.h), and OUT/dense_summary.json
// (counts, seconds per phase, and how close the dense points lie to the sparse model).
#include <filesystem>

#include "varsfm/dense/densify.h"
#include "varsfm/dense/sparse_distance.h"
#include "varsfm/util/option_check.h"

namespace varsfm {

struct DensifyOptions {
  // Optional: when given it must exist; densify itself needs only the sparse model and photos
  // (the model's 3D points are the propagation seeds).
  std::filesystem::path workspace;
  std::filesystem::path sparse;     // COLMAP model folder, or its parent: model 0
  std::filesystem::path image_dir;  // the photos, by the model's image names
  std::filesystem::path output;     // OUT/dense.ply is written
  DenseReconstructionOptions dense;
  int holdout = 0;  // every N-th registered image by name is left out (scene/holdout.h); 0: none

  // Throws OptionError (util/option_check.h) for a bad value; files are checked when the stage
  // runs.
  void Check() const;
};

struct DensifySummary {
  DenseMethod method = DenseMethod::kPatchMatch;
  DensifyStats stats;
  SparseDistanceStats quality;  // the dense points against the sparse model
  size_t num_points = 0;
  double seconds = 0;
};

// Throws varsfm::Error (one line) for a missing/unreadable model, a model with fewer than two
// registered images, a missing photo or one whose size differs from its camera.
DensifySummary RunDensify(const DensifyOptions& options,
                          OptionsCheck check = OptionsCheck::kByStage);

}  // namespace varsfm
