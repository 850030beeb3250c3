// Skinning buffers: the size contract shared by the skinning baselines (LBS, DQS).
//
//   transforms  one per skeleton joint
//   positions   one per model vertex
//   normals     one per model vertex, or none (normals skipped)
#pragma once

#include <cstddef>

#include "deform/baselines/skinning_table.h"

namespace sweepd::deform {

inline bool skinning_buffers_fit(const SkinningTable& table, std::size_t transforms,
                                 std::size_t positions, std::size_t normals) {
  return transforms == table.joint_count() && positions == table.vertex_count() &&
         (normals == 0 || normals == table.vertex_count());
}

}  // namespace sweepd::deform
