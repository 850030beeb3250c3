// Synthetic meshes with known collision answers, shared by the CPU and GPU collision tests:
// closed boxes, flat grids, random triangle soups, and a brute-force all-pairs reference.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <random>
#include <vector>

#include "deform/features/self_intersection.h"

namespace sweepd::deform::testing {

struct SoupMesh {
  std::vector<glm::vec3> positions;
  std::vector<std::uint32_t> indices;
  std::uint32_t triangle_count() const { return static_cast<std::uint32_t>(indices.size() / 3); }
  std::vector<std::uint32_t> all_triangles() const {
    std::vector<std::uint32_t> ids(triangle_count());
    for (std::uint32_t i = 0; i < ids.size(); ++i) ids[i] = i;
    return ids;
  }
};

// Axis-aligned closed box [lo, hi], 12 outward-facing triangles. Triangles 2f and 2f+1 form
// face f, in the order -x, +x, -y, +y, -z, +z.
inline void add_box(SoupMesh& mesh, glm::vec3 lo, glm::vec3 hi) {
  const auto base = static_cast<std::uint32_t>(mesh.positions.size());
  for (int i = 0; i < 8; ++i) {
    mesh.positions.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
  }
  // Each face as a quad (corner bits), counter-clockwise seen from outside.
  const int quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& q : quads) {
    for (int k : {q[0], q[1], q[2], q[0], q[2], q[3]}) mesh.indices.push_back(base + k);
  }
}

// n x n quads in a plane through `origin` spanned by u and v (each quad two triangles).
inline void add_grid(SoupMesh& mesh, glm::vec3 origin, glm::vec3 u, glm::vec3 v, int n) {
  const auto base = static_cast<std::uint32_t>(mesh.positions.size());
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      mesh.positions.push_back(origin + u * (static_cast<float>(i) / n) +
                               v * (static_cast<float>(j) / n));
    }
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const std::uint32_t a = base + j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      for (std::uint32_t k : {a, b, d, a, d, c}) mesh.indices.push_back(k);
    }
  }
}

// Closed box [lo, hi] with n cells along every edge; vertices shared across faces and edges,
// triangles outward-facing (so enclosed_volume gives the box's volume).
inline void add_subdivided_box(SoupMesh& mesh, glm::vec3 lo, glm::vec3 hi, int n) {
  std::vector<std::int64_t> index((n + 1) * (n + 1) * (n + 1), -1);
  auto vertex = [&](glm::ivec3 c) {
    std::int64_t& id = index[(c.x * (n + 1) + c.y) * (n + 1) + c.z];
    if (id < 0) {
      id = static_cast<std::int64_t>(mesh.positions.size());
      mesh.positions.push_back(lo + (hi - lo) * glm::vec3(c) / static_cast<float>(n));
    }
    return static_cast<std::uint32_t>(id);
  };
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    for (int at : {0, n}) {
      for (int u = 0; u < n; ++u) {
        for (int v = 0; v < n; ++v) {
          glm::ivec3 q[4];
          const int du[4] = {0, 1, 1, 0}, dv[4] = {0, 0, 1, 1};
          for (int k = 0; k < 4; ++k) q[k][a] = at, q[k][b] = u + du[k], q[k][c] = v + dv[k];
          if (at == 0) std::swap(q[1], q[3]);  // face -a: reverse so it faces outward
          for (int k : {0, 1, 2, 0, 2, 3}) mesh.indices.push_back(vertex(q[k]));
        }
      }
    }
  }
}

// `count` random triangles of edge length up to `size` in the unit cube (no shared vertices).
inline SoupMesh random_soup(int count, float size, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), offset(-size, size);
  SoupMesh mesh;
  for (int t = 0; t < count; ++t) {
    const glm::vec3 p(unit(rng), unit(rng), unit(rng));
    for (int k = 0; k < 3; ++k) {
      mesh.indices.push_back(static_cast<std::uint32_t>(mesh.positions.size()));
      mesh.positions.push_back(p + glm::vec3(offset(rng), offset(rng), offset(rng)));
    }
  }
  return mesh;
}

// Every pair of the listed triangles, tested exactly with no broad phase.
inline std::vector<TrianglePair> all_pairs_reference(const SoupMesh& mesh,
                                                     const std::vector<std::uint32_t>& ids) {
  std::vector<TrianglePair> pairs;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    for (std::size_t j = i + 1; j < ids.size(); ++j) {
      const std::uint32_t a = std::min(ids[i], ids[j]), b = std::max(ids[i], ids[j]);
      if (share_a_vertex(mesh.indices, a, b)) continue;
      if (mesh_triangles_intersect(mesh.positions, mesh.indices, a, b)) pairs.push_back({a, b});
    }
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

}  // namespace sweepd::deform::testing
