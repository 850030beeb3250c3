#include "mannequin/marching_tetrahedra.h"

#include <algorithm>
#include <array>
#include <unordered_map>

namespace sweepd::mannequin {

namespace {

constexpr int kBlockCells = 8;

// Cube corners are numbered by their offset bits: bit 0 = +x, bit 1 = +y, bit 2 = +z.
using Tetrahedron = std::array<int, 4>;

int determinant_sign(const Tetrahedron& tet) {
  auto offset = [](int corner) {
    return glm::ivec3(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
  };
  const glm::ivec3 a = offset(tet[1]) - offset(tet[0]);
  const glm::ivec3 b = offset(tet[2]) - offset(tet[0]);
  const glm::ivec3 c = offset(tet[3]) - offset(tet[0]);
  const int det =
      a.x * (b.y * c.z - b.z * c.y) - a.y * (b.x * c.z - b.z * c.x) + a.z * (b.x * c.y - b.y * c.x);
  return det > 0 ? 1 : -1;
}

// The 6 tetrahedra of the Kuhn split (paths 0 -> 7 along the axes), positively oriented.
std::array<Tetrahedron, 6> kuhn_tetrahedra() {
  std::array<Tetrahedron, 6> tets{};
  std::array<int, 3> axes = {0, 1, 2};
  int n = 0;
  do {
    const int first = 1 << axes[0];
    const int second = first | (1 << axes[1]);
    Tetrahedron tet = {0, first, second, 7};
    if (determinant_sign(tet) < 0) std::swap(tet[1], tet[2]);
    tets[n++] = tet;
  } while (std::next_permutation(axes.begin(), axes.end()));
  return tets;
}

bool is_even(const std::array<int, 4>& permutation) {
  int inversions = 0;
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b) inversions += permutation[a] > permutation[b] ? 1 : 0;
  return inversions % 2 == 0;
}

// Triangles (as tetrahedron edges, each a pair of local vertex ids) for every inside mask,
// oriented so their normal points from the inside vertices to the outside ones.
struct TriangleCase {
  int count = 0;
  std::array<std::array<std::array<int, 2>, 3>, 2> triangles{};
};

std::array<TriangleCase, 16> triangle_cases() {
  std::array<TriangleCase, 16> cases{};
  for (int mask = 1; mask < 15; ++mask) {
    const int inside = __builtin_popcount(mask);
    std::array<int, 4> p = {0, 1, 2, 3};
    do {
      if (!is_even(p)) continue;
      auto in = [&](int slot) { return ((mask >> p[slot]) & 1) != 0; };
      const int i = p[0], j = p[1], k = p[2], l = p[3];
      TriangleCase& c = cases[mask];
      if (inside == 1 && in(0)) {
        c.count = 1;
        c.triangles[0] = {{{i, j}, {i, k}, {i, l}}};
      } else if (inside == 3 && !in(0)) {
        c.count = 1;
        c.triangles[0] = {{{i, j}, {i, l}, {i, k}}};
      } else if (inside == 2 && in(0) && in(1)) {
        c.count = 2;
        c.triangles[0] = {{{i, k}, {i, l}, {j, l}}};
        c.triangles[1] = {{{i, k}, {j, l}, {j, k}}};
      } else {
        continue;
      }
      break;
    } while (std::next_permutation(p.begin(), p.end()));
  }
  return cases;
}

}  // namespace

void marching_tetrahedra(const SampleGrid& grid, const BlockField& field, IsoSurface& surface) {
  static const std::array<Tetrahedron, 6> kTets = kuhn_tetrahedra();
  static const std::array<TriangleCase, 16> kCases = triangle_cases();
  surface.positions.clear();
  surface.indices.clear();

  const std::int64_t stride_y = grid.cells.x + 1;
  const std::int64_t stride_z = stride_y * (grid.cells.y + 1);
  std::unordered_map<std::uint64_t, std::uint32_t> vertex_of_edge;
  std::vector<glm::vec3> points;
  std::vector<float> values;

  for (int bz = 0; bz < grid.cells.z; bz += kBlockCells) {
    for (int by = 0; by < grid.cells.y; by += kBlockCells) {
      for (int bx = 0; bx < grid.cells.x; bx += kBlockCells) {
        const glm::ivec3 first(bx, by, bz);
        const glm::ivec3 count = glm::min(glm::ivec3(kBlockCells), grid.cells - first);
        const glm::ivec3 sides = count + 1;  // points per axis
        points.clear();
        for (int k = 0; k < sides.z; ++k)
          for (int j = 0; j < sides.y; ++j)
            for (int i = 0; i < sides.x; ++i) points.push_back(grid.point(bx + i, by + j, bz + k));
        values.assign(points.size(), 0.0f);
        if (!field(points.front(), points.back(), points, values)) continue;
        bool any_inside = false, any_outside = false;
        for (float& v : values) {
          if (v == 0.0f) v = 1e-12f;  // exactly 0 counts as outside, so no vertex sits on a point
          (v < 0.0f ? any_inside : any_outside) = true;
        }
        if (!any_inside || !any_outside) continue;

        auto local = [&](int i, int j, int k) { return i + sides.x * (j + sides.y * k); };
        for (int k = 0; k < count.z; ++k) {
          for (int j = 0; j < count.y; ++j) {
            for (int i = 0; i < count.x; ++i) {
              std::array<float, 8> corner_value;
              std::array<int, 8> corner_local;
              int cube_mask = 0;
              for (int c = 0; c < 8; ++c) {
                corner_local[c] = local(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
                corner_value[c] = values[corner_local[c]];
                cube_mask |= (corner_value[c] < 0.0f ? 1 : 0) << c;
              }
              if (cube_mask == 0 || cube_mask == 255) continue;
              const std::int64_t cube_global =
                  (bx + i) + stride_y * (by + j) + stride_z * static_cast<std::int64_t>(bz + k);
              auto edge_vertex = [&](int ca, int cb) {
                if ((ca & cb) != ca) std::swap(ca, cb);  // ca's offset bits are a subset of cb's
                const std::int64_t lo_global = cube_global + (ca & 1) + stride_y * ((ca >> 1) & 1) +
                                               stride_z * ((ca >> 2) & 1);
                const std::uint64_t key = static_cast<std::uint64_t>(lo_global) * 8u +
                                          static_cast<std::uint64_t>(ca ^ cb);
                const auto [it, inserted] = vertex_of_edge.try_emplace(
                    key, static_cast<std::uint32_t>(surface.positions.size()));
                if (inserted) {
                  const float va = corner_value[ca], vb = corner_value[cb];
                  const float t = std::clamp(va / (va - vb), 0.01f, 0.99f);
                  const glm::vec3& pa = points[corner_local[ca]];
                  const glm::vec3& pb = points[corner_local[cb]];
                  surface.positions.push_back(pa + t * (pb - pa));
                }
                return it->second;
              };
              for (const Tetrahedron& tet : kTets) {
                int mask = 0;
                for (int v = 0; v < 4; ++v) mask |= ((cube_mask >> tet[v]) & 1) << v;
                const TriangleCase& c = kCases[mask];
                for (int t = 0; t < c.count; ++t)
                  for (const auto& edge : c.triangles[t])
                    surface.indices.push_back(edge_vertex(tet[edge[0]], tet[edge[1]]));
              }
            }
          }
        }
      }
    }
  }
}

}  // namespace sweepd::mannequin
