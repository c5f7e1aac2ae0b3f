#include "varsfm/mesh/hole_filling.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "varsfm/mesh/hole_fairing.h"
#include "varsfm/mesh/mesh_topology.h"
#include "varsfm/util/option_check.h"

namespace varsfm {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
constexpr uint32_t kNone = UINT32_MAX;

// A face's edge from -> to (counter-clockwise in the face) with the face's third vertex.
struct HalfEdge {
  uint32_t from, to, third;
};

// The undirected edges of the faces, sorted by key, one entry per face using them.
std::vector<std::pair<uint64_t, HalfEdge>> SortedEdges(const TriangleMesh& mesh) {
  std::vector<std::pair<uint64_t, HalfEdge>> edges;
  edges.reserve(3 * mesh.faces.size());
  for (const Eigen::Vector3i& f : mesh.faces)
    for (int k = 0; k < 3; ++k) {
      const auto a = static_cast<uint32_t>(f[k]), b = static_cast<uint32_t>(f[(k + 1) % 3]),
                 c = static_cast<uint32_t>(f[(k + 2) % 3]);
      edges.push_back({UndirectedEdgeKey(a, b), HalfEdge{a, b, c}});
    }
  std::sort(edges.begin(), edges.end(), [](const auto& x, const auto& y) {
    if (x.first != y.first) return x.first < y.first;
    return x.second.from != y.second.from ? x.second.from < y.second.from
                                          : x.second.third < y.second.third;
  });
  return edges;
}

// The boundary half-edges among the faces' edges of one undirected edge, [begin, end) of the
// sorted edges: an edge of one face is one. So is, at an edge of three faces, the face whose
// direction along the edge is left over when the other two pair up in opposite directions: where
// the cut leaves a flap on a hole's rim (a fourth face removed as long), the hole's boundary runs
// through the edge, and without it the loop would not close. Any other edge (two faces, or a
// fourth face beside two pairs, or faces that disagree in orientation) is not on the boundary.
void AddBoundaryHalfEdges(const std::vector<std::pair<uint64_t, HalfEdge>>& edges, size_t begin,
                          size_t end, std::vector<HalfEdge>* boundary) {
  if (end - begin == 1) {
    boundary->push_back(edges[begin].second);
    return;
  }
  if (end - begin != 3) return;
  // Sorted by `from`, the two faces of one direction are adjacent: one of them is left over.
  const HalfEdge &first = edges[begin].second, &last = edges[end - 1].second;
  const HalfEdge& middle = edges[begin + 1].second;
  if (first.from == middle.from && last.from != middle.from) boundary->push_back(first);
  if (last.from == middle.from && first.from != middle.from) boundary->push_back(last);
}

// Chains the boundary half-edges into simple loops (each a list of half-edges in the faces'
// direction, no vertex twice). At a vertex where several boundary loops meet (a pinch of the
// surface), the walk takes the unused outgoing edges in order and splits the closed walk into
// simple loops where it comes back to a vertex; a walk that ends where no edge leaves (the
// faces around disagree in orientation) yields nothing.
std::vector<std::vector<HalfEdge>> BoundaryLoops(const std::vector<HalfEdge>& boundary,
                                                 size_t num_vertices) {
  std::vector<uint32_t> first(num_vertices + 1, 0), order(boundary.size());
  for (const HalfEdge& h : boundary) ++first[h.from + 1];
  for (size_t v = 0; v < num_vertices; ++v) first[v + 1] += first[v];
  std::vector<uint32_t> fill(first.begin(), first.end() - 1);
  for (uint32_t e = 0; e < boundary.size(); ++e) order[fill[boundary[e].from]++] = e;
  std::vector<uint32_t> next_unused(first.begin(), first.end() - 1);
  const auto take = [&](uint32_t v) {
    return next_unused[v] < first[v + 1] ? order[next_unused[v]++] : kNone;
  };
  std::vector<uint32_t> position(num_vertices, kNone);  // in the current walk
  std::vector<std::vector<HalfEdge>> loops;
  for (uint32_t v = 0; v < num_vertices; ++v) {
    for (uint32_t e = take(v); e != kNone; e = take(v)) {
      std::vector<HalfEdge> walk{boundary[e]};
      position[v] = 0;
      uint32_t at = boundary[e].to;
      while (!walk.empty()) {
        if (position[at] != kNone) {  // back at a vertex of the walk: a simple loop closes
          const size_t p = position[at];
          for (size_t k = p; k < walk.size(); ++k) position[walk[k].from] = kNone;
          loops.emplace_back(walk.begin() + static_cast<ptrdiff_t>(p), walk.end());
          walk.resize(p);
          if (walk.empty()) break;
        }
        const uint32_t out = take(at);
        if (out == kNone) break;
        if (position[at] == kNone) position[at] = static_cast<uint32_t>(walk.size());
        walk.push_back(boundary[out]);
        at = boundary[out].to;
      }
      for (const HalfEdge& h : walk) position[h.from] = kNone;
    }
  }
  return loops;
}

double Perimeter(const TriangleMesh& mesh, const std::vector<HalfEdge>& loop) {
  double length = 0;
  for (const HalfEdge& h : loop) length += (mesh.vertices[h.to] - mesh.vertices[h.from]).norm();
  return length;
}

// The triangulation of one loop as faces of the mesh, oriented like the faces beside the loop;
// empty when CGAL finds none or a new inner edge is already an edge of the mesh (the patch would
// make it non-manifold).
std::vector<Eigen::Vector3i> TriangulateLoop(
    const TriangleMesh& mesh, const std::vector<HalfEdge>& loop,
    const std::vector<std::pair<uint64_t, HalfEdge>>& edges) {
  std::vector<Kernel::Point_3> points, thirds;
  for (const HalfEdge& h : loop) {
    const Eigen::Vector3d &p = mesh.vertices[h.from], &q = mesh.vertices[h.third];
    points.emplace_back(p.x(), p.y(), p.z());
    thirds.emplace_back(q.x(), q.y(), q.z());
  }
  std::vector<CGAL::Triple<int, int, int>> patch;
  CGAL::Polygon_mesh_processing::triangulate_hole_polyline(points, thirds,
                                                           std::back_inserter(patch));
  const int n = static_cast<int>(loop.size());
  if (patch.size() != loop.size() - 2) return {};
  // The patch must run each loop edge against the face beside it: from -> to there, to -> from
  // in the patch. Which way CGAL orders its triples, the triangle on loop edge 0 -> 1 says.
  bool reverse = false;
  std::vector<Eigen::Vector3i> faces;
  for (const auto& t : patch) {
    const int v[3] = {t.first, t.second, t.third};
    for (int k = 0; k < 3; ++k) {
      if (v[k] == 0 && v[(k + 1) % 3] == 1) reverse = true;
      const int a = v[k], b = v[(k + 1) % 3];
      const bool on_loop = (b - a + n) % n == 1 || (a - b + n) % n == 1;
      if (!on_loop &&
          std::binary_search(
              edges.begin(), edges.end(),
              std::pair<uint64_t, HalfEdge>{UndirectedEdgeKey(loop[a].from, loop[b].from), {}},
              [](const auto& x, const auto& y) { return x.first < y.first; }))
        return {};
    }
    faces.emplace_back(loop[v[0]].from, loop[v[1]].from, loop[v[2]].from);
  }
  if (reverse)
    for (Eigen::Vector3i& f : faces) std::swap(f[1], f[2]);
  return faces;
}

// The faces of each vertex, as offsets into one list.
struct VertexFaces {
  std::vector<uint32_t> begin;  // num_vertices + 1
  std::vector<uint32_t> faces;
};

VertexFaces FacesOfVertices(const TriangleMesh& mesh) {
  VertexFaces out;
  out.begin.assign(mesh.vertices.size() + 1, 0);
  for (const Eigen::Vector3i& f : mesh.faces)
    for (int k = 0; k < 3; ++k) ++out.begin[f[k] + 1];
  for (size_t v = 0; v < mesh.vertices.size(); ++v) out.begin[v + 1] += out.begin[v];
  out.faces.resize(out.begin.back());
  std::vector<uint32_t> fill(out.begin.begin(), out.begin.end() - 1);
  for (uint32_t f = 0; f < mesh.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) out.faces[fill[mesh.faces[f][k]]++] = f;
  return out;
}

// The faces touching a loop's vertices, each once, in face order.
std::vector<Eigen::Vector3i> RingOfLoop(const TriangleMesh& mesh, const VertexFaces& faces_of,
                                        const std::vector<HalfEdge>& loop) {
  std::vector<uint32_t> ids;
  for (const HalfEdge& h : loop)
    ids.insert(ids.end(), faces_of.faces.begin() + faces_of.begin[h.from],
               faces_of.faces.begin() + faces_of.begin[h.from + 1]);
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  std::vector<Eigen::Vector3i> ring;
  for (const uint32_t f : ids) ring.push_back(mesh.faces[f]);
  return ring;
}

}  // namespace

void HoleFillingOptions::Check() const { CheckNonNegative("--max-hole-edges", max_edges); }

HoleFillingStats FillSmallHoles(const HoleFillingOptions& options, TriangleMesh* mesh) {
  HoleFillingStats stats;
  if (options.max_edges < 3 || mesh->faces.empty()) return stats;
  const auto edges = SortedEdges(*mesh);
  std::vector<HalfEdge> boundary;
  std::vector<double> lengths;
  lengths.reserve(edges.size());
  for (size_t i = 0; i < edges.size();) {
    size_t end = i + 1;
    while (end < edges.size() && edges[end].first == edges[i].first) ++end;
    AddBoundaryHalfEdges(edges, i, end, &boundary);
    for (; i < end; ++i) {
      const HalfEdge& h = edges[i].second;
      lengths.push_back((mesh->vertices[h.to] - mesh->vertices[h.from]).squaredNorm());
    }
  }
  const auto middle = lengths.begin() + static_cast<ptrdiff_t>(lengths.size() / 2);
  std::nth_element(lengths.begin(), middle, lengths.end());
  const double median_edge = std::sqrt(*middle);
  const double max_perimeter = options.max_edges * median_edge;

  const std::vector<std::vector<HalfEdge>> loops = BoundaryLoops(boundary, mesh->vertices.size());
  stats.loops = loops.size();
  // The longest loop of each connected part is its outer edge.
  const std::vector<uint32_t> root = ComponentRoots(*mesh);
  std::vector<double> perimeters(loops.size());
  std::vector<size_t> outer(mesh->vertices.size(), SIZE_MAX);
  for (size_t l = 0; l < loops.size(); ++l) {
    perimeters[l] = Perimeter(*mesh, loops[l]);
    size_t& o = outer[root[loops[l][0].from]];
    if (o == SIZE_MAX || perimeters[l] > perimeters[o]) o = l;
  }
  const VertexFaces faces_of_vertex =
      options.refine_and_fair ? FacesOfVertices(*mesh) : VertexFaces{};
  std::vector<Eigen::Vector3d> new_vertices;
  for (size_t l = 0; l < loops.size(); ++l) {
    if (outer[root[loops[l][0].from]] == l) continue;
    if (loops[l].size() > static_cast<size_t>(options.max_edges) || perimeters[l] > max_perimeter)
      continue;
    std::vector<Eigen::Vector3i> patch = TriangulateLoop(*mesh, loops[l], edges);
    if (patch.empty()) continue;
    if (options.refine_and_fair) {
      // Liepa's density control splits a patch triangle while its centroid lies farther than
      // its corners' scale / sqrt(2) from each of them, a loop vertex's scale being the mean
      // length of its edges around the hole. The cut leaves holes rimmed by long edges, which
      // that alone would refine only to their length: the factor grows with the loop's mean edge
      // over the surface's median edge, so that the patch comes out at about its density.
      const double loop_edge = perimeters[l] / static_cast<double>(loops[l].size());
      const double density = std::sqrt(2.0) * std::max(1.0, loop_edge / median_edge);
      if (RefineAndFairPatch(*mesh, RingOfLoop(*mesh, faces_of_vertex, loops[l]), density, &patch,
                             &new_vertices))
        ++stats.faired_loops;
    }
    ++stats.filled_loops;
    stats.added_faces += patch.size();
    mesh->faces.insert(mesh->faces.end(), patch.begin(), patch.end());
  }
  stats.added_vertices = new_vertices.size();
  mesh->vertices.insert(mesh->vertices.end(), new_vertices.begin(), new_vertices.end());
  if (!mesh->colors.empty())
    mesh->colors.resize(mesh->vertices.size(), Eigen::Matrix<uint8_t, 3, 1>(128, 128, 128));
  return stats;
}

}  // namespace varsfm
