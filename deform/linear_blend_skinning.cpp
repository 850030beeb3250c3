#include "deform/linear_blend_skinning.h"

#include <cassert>
#include <cmath>
#include <tuple>

#include "deform/skinning_buffers.h"
#include "deform/vertex_blocks.h"

namespace sweepd::deform {

namespace {

// Vertices [begin, end): the columns of the blended matrix (4-wide), then position and normal.
template <bool kNormals>
void skin_block(const Model& model, std::span<const glm::mat4> skinning,
                std::span<glm::vec3> positions, std::span<glm::vec3> normals, std::size_t begin,
                std::size_t end) {
  for (std::size_t v = begin; v < end; ++v) {
    const auto& [w, j] = std::tie(model.skin_weights[v], model.skin_joints[v]);
    const float scale = 1.0f / (w[0] + w[1] + w[2] + w[3]);
    const glm::mat4& m0 = skinning[j[0]];
    const glm::mat4& m1 = skinning[j[1]];
    const glm::mat4& m2 = skinning[j[2]];
    const glm::mat4& m3 = skinning[j[3]];
    const float w0 = w[0] * scale, w1 = w[1] * scale, w2 = w[2] * scale, w3 = w[3] * scale;
    const glm::vec4 c0 = m0[0] * w0 + m1[0] * w1 + m2[0] * w2 + m3[0] * w3;
    const glm::vec4 c1 = m0[1] * w0 + m1[1] * w1 + m2[1] * w2 + m3[1] * w3;
    const glm::vec4 c2 = m0[2] * w0 + m1[2] * w1 + m2[2] * w2 + m3[2] * w3;
    const glm::vec4 c3 = m0[3] * w0 + m1[3] * w1 + m2[3] * w2 + m3[3] * w3;
    const glm::vec3 p = model.positions[v];
    positions[v] = glm::vec3(c0 * p.x + c1 * p.y + c2 * p.z + c3);
    if constexpr (kNormals) {
      const glm::vec3 n = model.normals[v];
      const glm::vec3 turned = glm::vec3(c0 * n.x + c1 * n.y + c2 * n.z);
      normals[v] = turned * (1.0f / std::sqrt(glm::dot(turned, turned)));
    }
  }
}

void skin_range(const Model& model, std::span<const glm::mat4> skinning,
                std::span<glm::vec3> positions, std::span<glm::vec3> normals, std::size_t begin,
                std::size_t end) {
  if (normals.empty()) {
    skin_block<false>(model, skinning, positions, normals, begin, end);
  } else {
    skin_block<true>(model, skinning, positions, normals, begin, end);
  }
}

}  // namespace

void linear_blend_skinning(const Model& model, std::span<const glm::mat4> skinning,
                           std::span<glm::vec3> positions, std::span<glm::vec3> normals) {
  assert(skinning_buffers_fit(model, skinning.size(), positions.size(), normals.size()));
  skin_range(model, skinning, positions, normals, 0, model.vertex_count());
}

void linear_blend_skinning_parallel(const Model& model, std::span<const glm::mat4> skinning,
                                    std::span<glm::vec3> positions, std::span<glm::vec3> normals,
                                    int threads) {
  assert(skinning_buffers_fit(model, skinning.size(), positions.size(), normals.size()));
  run_in_vertex_blocks(model.vertex_count(), threads, [&](std::size_t begin, std::size_t end) {
    skin_range(model, skinning, positions, normals, begin, end);
  });
}

}  // namespace sweepd::deform
