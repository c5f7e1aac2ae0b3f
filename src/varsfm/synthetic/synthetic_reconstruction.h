#pragma once
// A Reconstruction holding a synthetic scene (synthetic_scene.h) exactly, so tests and
// benchmarks of modules that consume a sparse model start from known ground truth.
#include "varsfm/scene/reconstruction.h"
#include "varsfm/synthetic/synthetic_scene.h"

namespace varsfm {

// Image i of the scene becomes image i + 1 with camera i + 1 (registered, true pose), its 2D
// points are the scene's observations in order (points2D[j] is scene.observations[i][j], so
// outlier flags can be looked up), and every point seen at least twice gets its true position.
Reconstruction ReconstructionFromSynthetic(const SyntheticScene& scene);

// Adds `camera` and, for image `index` of a synthetic scene, the registered image index + 1
// named "image<index>" at its true pose, without 2D points; returns it as stored in `rec`.
Image& AddTrueImage(int index, const Camera& camera, const Rigid3d& cam_from_world,
                    Reconstruction* rec);

}  // namespace varsfm
