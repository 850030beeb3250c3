// Dual-quaternion skinning (DQS): the second baseline — each vertex moves by the normalised
// weighted sum of its joints' unit dual quaternions, which keeps volume at twisted joints
// where LBS collapses ("candy wrapper"), at the price of bulging at bent ones.
//
//   table      the model's influences laid out once (skinning_table.h; ModelRuntime holds one)
//   skinning   table.joint_count() rigid matrices from skinning_matrices
//              (deform/model/forward_kinematics.h), each converted once per call to a unit dual
//              quaternion. Scale is not supported: each matrix's 3×3 columns are normalised
//              first, so joint scale is dropped (rotation + translation only).
//   positions  table.vertex_count() posed positions (output, caller-owned)
//   normals    table.vertex_count() posed unit normals (output; rotated by the blended
//              rotation), or empty to skip them.
//   threads    the items are split into this many blocks (deform/simd/vertex_blocks.h); results
//              are bit-identical for every count.
// Antipodality: a joint's quaternion whose real part points away from the vertex's first
// influence (its first with a positive weight; negative 4D dot product) is blended with its sign
// flipped, so q and -q (the same rotation) never cancel. The per-joint dual quaternions are
// converted once per call into a per-thread buffer that grows only when a skeleton with more joints
// comes along; otherwise nothing is allocated but the threads. The Model overload builds a table on
// the spot, for one-off calls.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <span>

#include "deform/baselines/skinning_table.h"
#include "deform/model/model.h"

namespace sweepd::deform {

// real: the rotation (unit); dual: 0.5 * (0, translation) * real.
struct DualQuaternion {
  glm::quat real{1, 0, 0, 0};
  glm::quat dual{0, 0, 0, 0};
};

// The unit dual quaternion of a rigid transform (3×3 columns normalised, see above).
DualQuaternion to_dual_quaternion(const glm::mat4& rigid);

void dual_quaternion_skinning(const SkinningTable& table, std::span<const glm::mat4> skinning,
                              std::span<glm::vec3> positions, std::span<glm::vec3> normals,
                              int threads = 1);

void dual_quaternion_skinning(const Model& model, std::span<const glm::mat4> skinning,
                              std::span<glm::vec3> positions, std::span<glm::vec3> normals);

}  // namespace sweepd::deform
