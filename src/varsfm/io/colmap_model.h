#pragma once
// A Reconstruction as a COLMAP sparse model, text (cameras.txt, images.txt, points3D.txt) or
// binary (cameras.bin, images.bin, points3D.bin), in the layouts COLMAP 3.8 reads
// (src/base/reconstruction.cc: ReadText/ReadBinary; binary is little-endian).
//
// Only registered images are written, as COLMAP does; every camera is written. varsfm already
// uses COLMAP's pixel convention and world-to-camera poses, so nothing is shifted or inverted.
#include <filesystem>
#include <string>
#include <vector>

#include "varsfm/scene/reconstruction.h"

namespace varsfm {

struct ColmapWriteOptions {
  bool binary = false;
  // -1: each camera gets SmallestColmapModel (exact up to skew). Otherwise every camera is
  // written with this COLMAP model id (e.g. kColmapOpenCV for a uniform model); parameters the
  // forced model lacks are lost, with a warning.
  int force_model_id = -1;
};

// Writes the model into `dir` (created if needed). The files are written into a temporary
// folder beside `dir` first and only renamed into place once all three are complete, so a
// failed write (full disk, bad camera) never leaves a half-written model. Throws varsfm::Error.
void WriteColmapModel(const Reconstruction& reconstruction, const std::filesystem::path& dir,
                      const ColmapWriteOptions& options = {});

// The model folder `path` names: `path` itself when it holds a model (cameras.bin or
// cameras.txt), else `path`/0 when that does: COLMAP's mapper writes its models as sparse/0,
// sparse/1, ... (largest first, as varsfm's `map`), and a tool given the parent means model 0.
// Otherwise `path` (whose reading then fails naming it).
std::filesystem::path ResolveColmapModelFolder(const std::filesystem::path& path);

// Reads the model in ResolveColmapModelFolder(`dir`): binary when cameras.bin, images.bin and
// points3D.bin exist, otherwise text. Every image read is registered. Point ids are renumbered 1,
// 2, ... in file order (Reconstruction assigns them); tracks and 2D links are kept. Throws
// varsfm::Error naming the file for a missing/truncated file, a bad line or a camera model varsfm
// cannot represent.
Reconstruction ReadColmapModel(const std::filesystem::path& dir);

}  // namespace varsfm
