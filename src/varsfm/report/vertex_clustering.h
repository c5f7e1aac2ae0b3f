#pragma once
// Fewer triangles for the report's 3D view, by vertex clustering (Rossignac & Borrel, "Multi-
// resolution 3D approximations for rendering complex scenes", 1993): the vertices within one
// cell of a regular grid become one vertex at their mean position, and triangles with two
// corners in one cell vanish. A textured mesh's vertices carry texture coordinates, which differ
// between the charts of the atlas that meet at a point: corners in one cell stay apart unless
// their coordinates fall in the same small square of the atlas (most likely the same chart),
// so each remaining triangle keeps the texture of its own chart.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace varsfm {

struct ClusteredPart {
  std::vector<float> positions;  // x, y, z per vertex
  std::vector<float> uvs;        // u, v per vertex (empty when the input had none)
  std::vector<uint32_t> indices;
};

// `parts` share one grid (a mesh split into parts by material stays one surface). The cell
// size is chosen, in a few trials, so that about `max_faces` triangles remain in all; parts
// with no more than that in total are returned unchanged.
std::vector<ClusteredPart> ClusterVertices(const std::vector<ClusteredPart>& parts,
                                           size_t max_faces);

}  // namespace varsfm
