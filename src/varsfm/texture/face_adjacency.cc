#include "varsfm/texture/face_adjacency.h"

#include <algorithm>
#include <unordered_map>

#include "varsfm/scene/triangle_mesh.h"

namespace varsfm {

std::vector<std::array<int, 3>> FaceNeighbours(const std::vector<Eigen::Vector3i>& faces) {
  std::vector<std::array<int, 3>> neighbours(faces.size(), {-1, -1, -1});
  // Undirected edge -> the first (face, slot) that used it, until its partner is found.
  std::unordered_map<uint64_t, std::pair<int, int>> open;
  open.reserve(faces.size() * 2);
  for (size_t f = 0; f < faces.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const uint64_t key = UndirectedEdgeKey(faces[f][k], faces[f][(k + 1) % 3]);
      const auto [it, inserted] = open.try_emplace(key, static_cast<int>(f), k);
      if (inserted) continue;
      const auto [g, slot] = it->second;
      if (g >= 0 && g != static_cast<int>(f)) {
        neighbours[f][k] = g;
        neighbours[g][slot] = static_cast<int>(f);
        it->second.first = -1;  // linked: later faces on this edge stay unlinked
      }
    }
  }
  return neighbours;
}

}  // namespace varsfm
