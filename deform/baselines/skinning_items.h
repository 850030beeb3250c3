// What the skinning loops (LBS, DQS) share: a group's items as pointers into a SkinningTable,
// the stores of a result, the walk over the groups that fall in a range of items, and the
// table of a method's loops per (influences, normals) and instruction set.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <glm/glm.hpp>
#include <span>
#include <utility>

#include "deform/baselines/skinning_table.h"
#include "deform/simd/float_lanes.h"

namespace sweepd::deform {

// One group's items from its first in a range: item i moves vertex[i]; its influences follow
// one another in joint/weight.
struct SkinningItems {
  const std::uint32_t* vertex;
  const glm::vec4* position;  // (p, 1)
  const glm::vec4* normal;    // (n, 0)
  const std::uint32_t* joint;
  const float* weight;
};

inline void store_lanes(glm::vec3& out, FloatLanes lanes) {
  std::memcpy(&out, &lanes, sizeof(glm::vec3));
}

inline FloatLanes unit_lanes(FloatLanes v) {
  return v * (1.0f / std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
}

// An item with no influence stays at rest.
inline void store_rest(const SkinningItems& d, std::size_t i, glm::vec3* positions,
                       glm::vec3* normals, bool with_normals) {
  store_lanes(positions[d.vertex[i]], load_lanes(&d.position[i].x));
  if (with_normals) store_lanes(normals[d.vertex[i]], load_lanes(&d.normal[i].x));
}

// Calls run(group's influences, items, count) for each group's part of items [begin, end).
template <class Run>
void for_each_group_in(const SkinningTable& table, std::size_t begin, std::size_t end,
                       const Run& run) {
  for (const SkinningTable::Group& group : table.groups()) {
    const std::size_t from = std::max(begin, group.begin), to = std::min(end, group.end);
    if (from >= to) continue;
    const std::size_t first = group.first_influence + (from - group.begin) * group.influences;
    run(group.influences,
        SkinningItems{table.vertices().data() + from, table.rest_positions().data() + from,
                      table.rest_normals().data() + from, table.joints().data() + first,
                      table.weights().data() + first},
        to - from);
  }
}

// Method::baseline<kJoints, kNormals> and, on x86-64, Method::avx2<kJoints, kNormals> (each a
// Method::Loop) for kJoints 0..kInfluences; the result is indexed by influences * 2 + normals.
template <class Method>
const std::array<typename Method::Loop, 2 * (kInfluences + 1)>& skinning_loops(
    VertexLoopInstructions instructions) {
  using Loops = std::array<typename Method::Loop, 2 * (kInfluences + 1)>;
  constexpr auto every = std::make_integer_sequence<int, 2 * (kInfluences + 1)>();
  static constexpr Loops baseline = []<int... kLoop>(std::integer_sequence<int, kLoop...>) {
    return Loops{Method::template baseline<kLoop / 2, kLoop % 2 == 1>...};
  }
  (every);
#if defined(__x86_64__)
  static constexpr Loops avx2 = []<int... kLoop>(std::integer_sequence<int, kLoop...>) {
    return Loops{Method::template avx2<kLoop / 2, kLoop % 2 == 1>...};
  }
  (every);
  if (instructions == VertexLoopInstructions::kAvx2Fma) return avx2;
#endif
  (void)instructions;
  return baseline;
}

}  // namespace sweepd::deform
