#include "deform/baselines/linear_blend_skinning.h"

#include <cassert>
#include <cmath>
#include <tuple>

#include "deform/baselines/skinning_buffers.h"
#include "deform/simd/float_lanes.h"
#include "deform/simd/vertex_blocks.h"

namespace sweepd::deform {

namespace {

FloatLanes column(const glm::mat4& m, int c) { return load_lanes(&m[c][0]); }

// Vertices [begin, end): the columns of the blended matrix (4 lanes), then position and normal.
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
    FloatLanes c[4];
    for (int k = 0; k < 4; ++k)
      c[k] = column(m0, k) * w0 + column(m1, k) * w1 + column(m2, k) * w2 + column(m3, k) * w3;
    const glm::vec3 p = model.positions[v];
    const FloatLanes moved = c[0] * p.x + c[1] * p.y + c[2] * p.z + c[3];
    positions[v] = glm::vec3(moved[0], moved[1], moved[2]);
    if constexpr (kNormals) {
      const glm::vec3 n = model.normals[v];
      const FloatLanes turned = c[0] * n.x + c[1] * n.y + c[2] * n.z;
      const float inverse_length =
          1.0f / std::sqrt(turned[0] * turned[0] + turned[1] * turned[1] + turned[2] * turned[2]);
      normals[v] = glm::vec3(turned[0], turned[1], turned[2]) * inverse_length;
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
