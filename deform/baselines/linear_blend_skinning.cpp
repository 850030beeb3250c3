#include "deform/baselines/linear_blend_skinning.h"

#include <array>
#include <cassert>
#include <cstring>
#include <utility>

#include "deform/baselines/skinning_buffers.h"
#include "deform/baselines/skinning_items.h"
#include "deform/simd/vertex_blocks.h"

namespace sweepd::deform {

namespace {

// Items [0, count) with kJoints influences each, 4 lanes (SSE2, NEON): the blended matrix's four
// columns, then the position and the normal.
template <int kJoints, bool kNormals>
void skin_items_baseline(SkinningItems d, std::size_t count, const glm::mat4* skinning,
                         glm::vec3* positions, glm::vec3* normals) {
  for (std::size_t i = 0; i < count; ++i) {
    if constexpr (kJoints == 0) {
      store_rest(d, i, positions, normals, kNormals);
    } else {
      FloatLanes c[4] = {};
      for (int k = 0; k < kJoints; ++k, ++d.joint, ++d.weight) {
        const float* m = &skinning[*d.joint][0][0];
        for (int col = 0; col < 4; ++col) c[col] += load_lanes(m + 4 * col) * *d.weight;
      }
      const glm::vec4& p = d.position[i];
      store_lanes(positions[d.vertex[i]], c[0] * p.x + c[1] * p.y + c[2] * p.z + c[3]);
      if constexpr (kNormals) {
        const glm::vec4& n = d.normal[i];
        store_lanes(normals[d.vertex[i]], unit_lanes(c[0] * n.x + c[1] * n.y + c[2] * n.z));
      }
    }
  }
}

#if defined(__x86_64__)
// The same with 8 lanes (AVX2, FMA): columns 0|1 and 2|3 of the blended matrix; a transformed
// point is the sum of the two halves of columns01 * (x|y) + columns23 * (z|w).
template <int kJoints, bool kNormals>
[[gnu::target("avx2,fma")]] void skin_items_avx2(SkinningItems d, std::size_t count,
                                                 const glm::mat4* skinning, glm::vec3* positions,
                                                 glm::vec3* normals) {
  for (std::size_t i = 0; i < count; ++i) {
    if constexpr (kJoints == 0) {
      store_rest(d, i, positions, normals, kNormals);
    } else {
      FloatLanes8 c01 = {}, c23 = {};
      for (int k = 0; k < kJoints; ++k, ++d.joint, ++d.weight) {
        const float* m = &skinning[*d.joint][0][0];
        FloatLanes8 m01, m23;
        std::memcpy(&m01, m, sizeof(m01));
        std::memcpy(&m23, m + 8, sizeof(m23));
        c01 += m01 * *d.weight;
        c23 += m23 * *d.weight;
      }
      const FloatLanes p = load_lanes(&d.position[i].x);
      const FloatLanes8 moved = c01 * __builtin_shufflevector(p, p, 0, 0, 0, 0, 1, 1, 1, 1) +
                                c23 * __builtin_shufflevector(p, p, 2, 2, 2, 2, 3, 3, 3, 3);
      store_lanes(positions[d.vertex[i]], __builtin_shufflevector(moved, moved, 0, 1, 2, 3) +
                                              __builtin_shufflevector(moved, moved, 4, 5, 6, 7));
      if constexpr (kNormals) {
        const FloatLanes n = load_lanes(&d.normal[i].x);  // w = 0: column 3 drops out
        const FloatLanes8 turned = c01 * __builtin_shufflevector(n, n, 0, 0, 0, 0, 1, 1, 1, 1) +
                                   c23 * __builtin_shufflevector(n, n, 2, 2, 2, 2, 3, 3, 3, 3);
        store_lanes(normals[d.vertex[i]],
                    unit_lanes(__builtin_shufflevector(turned, turned, 0, 1, 2, 3) +
                               __builtin_shufflevector(turned, turned, 4, 5, 6, 7)));
      }
    }
  }
}
#endif

// The loops, for skinning_loops.
struct LinearBlendLoops {
  using Loop = void (*)(SkinningItems, std::size_t, const glm::mat4*, glm::vec3*, glm::vec3*);
  template <int kJoints, bool kNormals>
  static constexpr Loop baseline = &skin_items_baseline<kJoints, kNormals>;
#if defined(__x86_64__)
  template <int kJoints, bool kNormals>
  static constexpr Loop avx2 = &skin_items_avx2<kJoints, kNormals>;
#endif
};

void skin_range(const SkinningTable& table, std::span<const glm::mat4> skinning,
                std::span<glm::vec3> positions, std::span<glm::vec3> normals, std::size_t begin,
                std::size_t end) {
  const auto& loops = skinning_loops<LinearBlendLoops>(table.instructions());
  for_each_group_in(table, begin, end,
                    [&](int influences, const SkinningItems& items, std::size_t count) {
                      loops[influences * 2 + (normals.empty() ? 0 : 1)](
                          items, count, skinning.data(), positions.data(), normals.data());
                    });
}

}  // namespace

void linear_blend_skinning(const SkinningTable& table, std::span<const glm::mat4> skinning,
                           std::span<glm::vec3> positions, std::span<glm::vec3> normals,
                           int threads) {
  assert(skinning_buffers_fit(table, skinning.size(), positions.size(), normals.size()));
  run_in_vertex_blocks(
      table.item_count(), threads,
      [&](std::size_t begin, std::size_t end) {
        skin_range(table, skinning, positions, normals, begin, end);
      },
      kSkinningChunk);
}

void linear_blend_skinning(const Model& model, std::span<const glm::mat4> skinning,
                           std::span<glm::vec3> positions, std::span<glm::vec3> normals) {
  linear_blend_skinning(SkinningTable(model), skinning, positions, normals);
}

}  // namespace sweepd::deform
