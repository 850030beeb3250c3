#include "deform/mesh/mesh_topology.h"

#include <algorithm>
#include <array>
#include <bit>
#include <unordered_map>

#include "deform/mesh/disjoint_sets.h"

namespace sweepd::deform {

namespace {

struct PositionKey {
  std::array<std::uint32_t, 3> bits;
  bool operator==(const PositionKey&) const = default;
};

struct PositionKeyHash {
  std::size_t operator()(const PositionKey& key) const {
    std::uint64_t h = 1469598103934665603ull;
    for (std::uint32_t b : key.bits) h = (h ^ b) * 1099511628211ull;
    return static_cast<std::size_t>(h);
  }
};

PositionKey key_of(const glm::vec3& p) {
  // Adding +0 turns -0 into +0, so the two compare equal as bits too.
  return {{std::bit_cast<std::uint32_t>(p.x + 0.0f), std::bit_cast<std::uint32_t>(p.y + 0.0f),
           std::bit_cast<std::uint32_t>(p.z + 0.0f)}};
}

// Welded, non-degenerate triangles of the input.
struct WeldedTriangles {
  std::size_t vertex_count = 0;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::size_t degenerate = 0;
};

WeldedTriangles weld_triangles(std::span<const glm::vec3> positions,
                               std::span<const std::uint32_t> indices) {
  WeldedTriangles result;
  const std::vector<std::uint32_t> welded =
      weld_coincident_positions(positions, &result.vertex_count);
  result.triangles.reserve(indices.size() / 3);
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
    const std::array<std::uint32_t, 3> tri = {welded[indices[t]], welded[indices[t + 1]],
                                              welded[indices[t + 2]]};
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0]) {
      ++result.degenerate;
      continue;
    }
    result.triangles.push_back(tri);
  }
  return result;
}

// Vertices whose link (the edges opposite them in their triangles) is not one connected piece.
std::size_t count_non_manifold_vertices(const WeldedTriangles& mesh) {
  std::vector<std::uint32_t> start(mesh.vertex_count + 1, 0);
  for (const auto& tri : mesh.triangles)
    for (std::uint32_t v : tri) ++start[v + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<std::array<std::uint32_t, 2>> link(start.back());
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (const auto& tri : mesh.triangles)
    for (int k = 0; k < 3; ++k) link[fill[tri[k]]++] = {tri[(k + 1) % 3], tri[(k + 2) % 3]};

  std::size_t count = 0;
  std::vector<std::uint32_t> nodes;
  for (std::size_t v = 0; v < mesh.vertex_count; ++v) {
    if (start[v] == start[v + 1]) continue;
    nodes.clear();
    for (std::uint32_t e = start[v]; e < start[v + 1]; ++e)
      for (std::uint32_t n : link[e]) nodes.push_back(n);
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    DisjointSets sets(nodes.size());
    auto local = [&](std::uint32_t n) {
      return static_cast<std::uint32_t>(std::lower_bound(nodes.begin(), nodes.end(), n) -
                                        nodes.begin());
    };
    std::size_t pieces = nodes.size();
    for (std::uint32_t e = start[v]; e < start[v + 1]; ++e) {
      const std::uint32_t a = sets.find(local(link[e][0]));
      const std::uint32_t b = sets.find(local(link[e][1]));
      if (a != b) {
        sets.join(a, b);
        --pieces;
      }
    }
    if (pieces > 1) ++count;
  }
  return count;
}

}  // namespace

std::vector<std::uint32_t> weld_coincident_positions(std::span<const glm::vec3> positions,
                                                     std::size_t* welded_count) {
  std::unordered_map<PositionKey, std::uint32_t, PositionKeyHash> first_of;
  first_of.reserve(positions.size());
  std::vector<std::uint32_t> welded(positions.size());
  for (std::size_t v = 0; v < positions.size(); ++v) {
    const auto [it, inserted] =
        first_of.try_emplace(key_of(positions[v]), static_cast<std::uint32_t>(first_of.size()));
    welded[v] = it->second;
  }
  if (welded_count != nullptr) *welded_count = first_of.size();
  return welded;
}

MeshTopology analyze_topology(std::span<const glm::vec3> positions,
                              std::span<const std::uint32_t> indices) {
  const WeldedTriangles mesh = weld_triangles(positions, indices);
  MeshTopology topology;
  topology.triangles = mesh.triangles.size();
  topology.degenerate_triangles = mesh.degenerate;

  // Half-edges sorted by undirected edge; the low bit says which way round the triangle runs.
  std::vector<std::uint64_t> half_edges;
  half_edges.reserve(mesh.triangles.size() * 3);
  std::vector<bool> referenced(mesh.vertex_count, false);
  DisjointSets pieces(mesh.vertex_count);
  for (const auto& tri : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t a = tri[k], b = tri[(k + 1) % 3];
      half_edges.push_back((std::min(a, b) << 33) | (std::max(a, b) << 1) | (a < b ? 0u : 1u));
      referenced[a] = true;
      pieces.join(tri[k], tri[(k + 1) % 3]);
    }
  }
  std::sort(half_edges.begin(), half_edges.end());
  for (std::size_t i = 0; i < half_edges.size();) {
    std::size_t j = i;
    std::size_t forward = 0;
    while (j < half_edges.size() && (half_edges[j] >> 1) == (half_edges[i] >> 1)) {
      forward += (half_edges[j] & 1u) == 0 ? 1 : 0;
      ++j;
    }
    const std::size_t uses = j - i;
    ++topology.edges;
    if (uses == 1) ++topology.boundary_edges;
    if (uses > 2) ++topology.non_manifold_edges;
    if (uses == 2 && forward != 1) ++topology.inconsistent_edges;
    i = j;
  }

  for (std::uint32_t v = 0; v < mesh.vertex_count; ++v) {
    if (!referenced[v]) {
      ++topology.unreferenced_vertices;
      continue;
    }
    ++topology.welded_vertices;
    if (pieces.find(v) == v) ++topology.components;
  }
  topology.non_manifold_vertices = count_non_manifold_vertices(mesh);
  topology.euler_characteristic = static_cast<long>(topology.welded_vertices) -
                                  static_cast<long>(topology.edges) +
                                  static_cast<long>(topology.triangles);
  to_tri_mesh(positions, indices, &topology.faces_rejected_by_openmesh);
  return topology;
}

TriMesh to_tri_mesh(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                    std::size_t* rejected_faces) {
  std::size_t welded_count = 0;
  const std::vector<std::uint32_t> welded = weld_coincident_positions(positions, &welded_count);
  std::vector<glm::vec3> welded_positions(welded_count);
  for (std::size_t v = 0; v < positions.size(); ++v) welded_positions[welded[v]] = positions[v];

  TriMesh mesh;
  mesh.reserve(welded_count, welded_count * 3, indices.size() / 3);
  std::vector<TriMesh::VertexHandle> handles;
  handles.reserve(welded_count);
  for (const glm::vec3& p : welded_positions)
    handles.push_back(mesh.add_vertex(TriMesh::Point(p.x, p.y, p.z)));

  std::size_t rejected = 0;
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
    const std::uint32_t a = welded[indices[t]], b = welded[indices[t + 1]],
                        c = welded[indices[t + 2]];
    if (a == b || b == c || c == a || !mesh.add_face(handles[a], handles[b], handles[c]).is_valid())
      ++rejected;
  }
  if (rejected_faces != nullptr) *rejected_faces = rejected;
  return mesh;
}

}  // namespace sweepd::deform
