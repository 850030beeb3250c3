#include "deform/baselines/dual_quaternion_skinning.h"

#include <cassert>
#include <cmath>
#include <tuple>
#include <vector>

#include "deform/baselines/skinning_buffers.h"
#include "deform/simd/float_lanes.h"
#include "deform/simd/vertex_blocks.h"

namespace sweepd::deform {

namespace {

// A joint's dual quaternion as two lane sets, (x, y, z, w) each.
struct DualQuaternionLanes {
  FloatLanes real, dual;
};

// Converts every skinning matrix into the calling thread's buffer.
std::span<const DualQuaternionLanes> joint_dual_quaternions(std::span<const glm::mat4> skinning) {
  thread_local std::vector<DualQuaternionLanes> buffer;
  if (buffer.size() < skinning.size()) buffer.resize(skinning.size());
  for (std::size_t j = 0; j < skinning.size(); ++j) {
    const DualQuaternion q = to_dual_quaternion(skinning[j]);
    buffer[j] = {FloatLanes{q.real.x, q.real.y, q.real.z, q.real.w},
                 FloatLanes{q.dual.x, q.dual.y, q.dual.z, q.dual.w}};
  }
  return std::span<const DualQuaternionLanes>(buffer.data(), skinning.size());
}

template <bool kNormals>
void skin_block(const Model& model, std::span<const DualQuaternionLanes> joint_dq,
                std::span<glm::vec3> positions, std::span<glm::vec3> normals, std::size_t begin,
                std::size_t end) {
  for (std::size_t v = begin; v < end; ++v) {
    const auto& [w, j] = std::tie(model.skin_weights[v], model.skin_joints[v]);
    const DualQuaternionLanes& first = joint_dq[j[0]];
    FloatLanes real = first.real * w[0];
    FloatLanes dual = first.dual * w[0];
    for (int k = 1; k < kInfluences; ++k) {
      const DualQuaternionLanes& q = joint_dq[j[k]];
      const float signed_weight = sum_of_lanes(q.real * first.real) < 0.0f ? -w[k] : w[k];
      real += q.real * signed_weight;
      dual += q.dual * signed_weight;
    }
    const float inverse_length = 1.0f / std::sqrt(sum_of_lanes(real * real));
    real *= inverse_length;
    dual *= inverse_length;
    // Rotation by the unit real part, translation 2 * (dual * conj(real)).xyz (Kavan et al.).
    const glm::vec3 r(real[0], real[1], real[2]), d(dual[0], dual[1], dual[2]);
    const float rw = real[3], dw = dual[3];
    const glm::vec3 translation = 2.0f * (rw * d - dw * r + glm::cross(r, d));
    const glm::vec3 p = model.positions[v];
    positions[v] = p + 2.0f * glm::cross(r, glm::cross(r, p) + rw * p) + translation;
    if constexpr (kNormals) {
      const glm::vec3 n = model.normals[v];
      // A unit quaternion turns the unit rest normal into a unit normal: no renormalisation.
      normals[v] = n + 2.0f * glm::cross(r, glm::cross(r, n) + rw * n);
    }
  }
}

void skin_range(const Model& model, std::span<const DualQuaternionLanes> joint_dq,
                std::span<glm::vec3> positions, std::span<glm::vec3> normals, std::size_t begin,
                std::size_t end) {
  if (normals.empty()) {
    skin_block<false>(model, joint_dq, positions, normals, begin, end);
  } else {
    skin_block<true>(model, joint_dq, positions, normals, begin, end);
  }
}

}  // namespace

DualQuaternion to_dual_quaternion(const glm::mat4& rigid) {
  const glm::mat3 rotation(glm::normalize(glm::vec3(rigid[0])), glm::normalize(glm::vec3(rigid[1])),
                           glm::normalize(glm::vec3(rigid[2])));
  DualQuaternion q;
  q.real = glm::normalize(glm::quat_cast(rotation));
  const glm::vec3 t(rigid[3]);
  q.dual = glm::quat(0.0f, t.x, t.y, t.z) * q.real * 0.5f;
  return q;
}

void dual_quaternion_skinning(const Model& model, std::span<const glm::mat4> skinning,
                              std::span<glm::vec3> positions, std::span<glm::vec3> normals) {
  assert(skinning_buffers_fit(model, skinning.size(), positions.size(), normals.size()));
  skin_range(model, joint_dual_quaternions(skinning), positions, normals, 0, model.vertex_count());
}

void dual_quaternion_skinning_parallel(const Model& model, std::span<const glm::mat4> skinning,
                                       std::span<glm::vec3> positions, std::span<glm::vec3> normals,
                                       int threads) {
  assert(skinning_buffers_fit(model, skinning.size(), positions.size(), normals.size()));
  const std::span<const DualQuaternionLanes> joint_dq = joint_dual_quaternions(skinning);
  run_in_vertex_blocks(model.vertex_count(), threads, [&](std::size_t begin, std::size_t end) {
    skin_range(model, joint_dq, positions, normals, begin, end);
  });
}

}  // namespace sweepd::deform
