#include "deform/dual_quaternion_skinning.h"

#include <cassert>
#include <cmath>
#include <tuple>
#include <vector>

#include "deform/skinning_buffers.h"
#include "deform/vertex_blocks.h"

namespace sweepd::deform {

namespace {

float dot4(const glm::quat& a, const glm::quat& b) {
  return a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z;
}

// Converts every skinning matrix into the calling thread's buffer.
std::span<const DualQuaternion> joint_dual_quaternions(std::span<const glm::mat4> skinning) {
  thread_local std::vector<DualQuaternion> buffer;
  if (buffer.size() < skinning.size()) buffer.resize(skinning.size());
  for (std::size_t j = 0; j < skinning.size(); ++j) buffer[j] = to_dual_quaternion(skinning[j]);
  return std::span<const DualQuaternion>(buffer.data(), skinning.size());
}

void skin_block(const Model& model, std::span<const DualQuaternion> joint_dq,
                std::span<glm::vec3> positions, std::span<glm::vec3> normals, std::size_t begin,
                std::size_t end) {
  const bool with_normals = !normals.empty();
  for (std::size_t v = begin; v < end; ++v) {
    const auto& [w, j] = std::tie(model.skin_weights[v], model.skin_joints[v]);
    const DualQuaternion& first = joint_dq[j[0]];
    glm::vec4 real = glm::vec4(first.real.x, first.real.y, first.real.z, first.real.w) * w[0];
    glm::vec4 dual = glm::vec4(first.dual.x, first.dual.y, first.dual.z, first.dual.w) * w[0];
    for (int k = 1; k < kInfluences; ++k) {
      const DualQuaternion& q = joint_dq[j[k]];
      const float signed_weight = dot4(q.real, first.real) < 0.0f ? -w[k] : w[k];
      real += glm::vec4(q.real.x, q.real.y, q.real.z, q.real.w) * signed_weight;
      dual += glm::vec4(q.dual.x, q.dual.y, q.dual.z, q.dual.w) * signed_weight;
    }
    const float inverse_length = 1.0f / std::sqrt(glm::dot(real, real));
    real *= inverse_length;
    dual *= inverse_length;
    // Rotation by the unit real part, translation 2 * (dual * conj(real)).xyz (Kavan et al.).
    const glm::vec3 r(real), d(dual);
    const float rw = real.w, dw = dual.w;
    const glm::vec3 translation = 2.0f * (rw * d - dw * r + glm::cross(r, d));
    const glm::vec3 p = model.positions[v];
    positions[v] = p + 2.0f * glm::cross(r, glm::cross(r, p) + rw * p) + translation;
    if (with_normals) {
      const glm::vec3 n = model.normals[v];
      const glm::vec3 turned = n + 2.0f * glm::cross(r, glm::cross(r, n) + rw * n);
      normals[v] = turned * (1.0f / std::sqrt(glm::dot(turned, turned)));
    }
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
  skin_block(model, joint_dual_quaternions(skinning), positions, normals, 0, model.vertex_count());
}

void dual_quaternion_skinning_parallel(const Model& model, std::span<const glm::mat4> skinning,
                                       std::span<glm::vec3> positions, std::span<glm::vec3> normals,
                                       int threads) {
  assert(skinning_buffers_fit(model, skinning.size(), positions.size(), normals.size()));
  const std::span<const DualQuaternion> joint_dq = joint_dual_quaternions(skinning);
  run_in_vertex_blocks(model.vertex_count(), threads, [&](std::size_t begin, std::size_t end) {
    skin_block(model, joint_dq, positions, normals, begin, end);
  });
}

}  // namespace sweepd::deform
