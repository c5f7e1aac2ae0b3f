#pragma once
// A compact copy of the textured model (OUT/model.glb, texture/gltf_writer.h) for the report's
// 3D view, so that the page stays a few megabytes: at most max_faces triangles, positions and
// texture coordinates quantised to 16 bits (glTF accessors with "normalized": true, dequantised by
// the node's scale and translation), 16-bit indices where they fit, and each atlas page re-encoded
// as a JPEG of at most max_texture_size pixels per side, resampled to powers of two so that WebGL 1
// can mip-map it without the browser resizing it again. Texture coordinates are normalised, so the
// page may change aspect. The copy is in the vertex data's frame, the sparse model's: the
// original node's half turn to glTF's y-up is not kept, since the view draws the cameras and
// points in that frame too.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace varsfm {

struct DisplayModelOptions {
  // Above this many triangles the copy is simplified by vertex clustering (vertex_clustering.h):
  // fountain-P11's 1.4 M-face model would otherwise make a 20 MB page.
  size_t max_faces = 100000;
  int max_texture_size = 2048;
  int jpeg_quality = 80;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

// Throws varsfm::Error (one line) when `glb` is not a binary glTF 2.0 file with triangle
// primitives whose positions and texture coordinates are 32-bit floats.
std::vector<uint8_t> CompactGlbForDisplay(const std::vector<uint8_t>& glb,
                                          const DisplayModelOptions& options = {});

}  // namespace varsfm
