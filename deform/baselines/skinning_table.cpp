#include "deform/baselines/skinning_table.h"

#include <stdexcept>
#include <string>

namespace sweepd::deform {

SkinningTable::SkinningTable(const Model& model, VertexLoopInstructions instructions)
    : instructions_(instructions),
      vertex_count_(model.vertex_count()),
      joint_count_(model.skeleton.joints.size()) {
  if (instructions == VertexLoopInstructions::kAvx2Fma &&
      widest_vertex_loop_instructions() != VertexLoopInstructions::kAvx2Fma)
    throw std::invalid_argument("skinning table: this CPU has no AVX2 with FMA");
  const std::size_t n = model.vertex_count();
  if (model.skin_joints.size() != n || model.skin_weights.size() != n ||
      (!model.normals.empty() && model.normals.size() != n))
    throw std::invalid_argument("skinning table: " + std::to_string(model.skin_joints.size()) +
                                " skin joint sets, " + std::to_string(model.skin_weights.size()) +
                                " weight sets and " + std::to_string(model.normals.size()) +
                                " normals for " + std::to_string(n) + " vertices");
  const auto influences_of = [&](std::size_t v) {
    int count = 0;
    for (const float w : model.skin_weights[v]) count += w > 0.0f;
    return count;
  };
  std::vector<std::vector<std::uint32_t>> by_count(kInfluences + 1);
  for (std::size_t v = 0; v < n; ++v)
    by_count[influences_of(v)].push_back(static_cast<std::uint32_t>(v));
  vertex_.reserve(n + (kInfluences + 1) * kSkinningChunk);
  rest_position_.reserve(n);
  rest_normal_.reserve(n);
  for (int count = 0; count <= kInfluences; ++count) {
    if (by_count[count].empty()) continue;
    std::vector<std::uint32_t>& members = by_count[count];
    members.resize((members.size() + kSkinningChunk - 1) / kSkinningChunk * kSkinningChunk,
                   members.back());
    groups_.push_back({count, vertex_.size(), vertex_.size() + members.size(), joint_.size()});
    for (const std::uint32_t v : members) {
      vertex_.push_back(v);
      rest_position_.emplace_back(model.positions[v], 1.0f);
      rest_normal_.emplace_back(model.normals.empty() ? glm::vec3(0.0f) : model.normals[v], 0.0f);
      const auto& w = model.skin_weights[v];
      float sum = 0.0f;
      for (int k = 0; k < kInfluences; ++k) sum += w[k] > 0.0f ? w[k] : 0.0f;
      for (int k = 0; k < kInfluences; ++k) {
        if (w[k] <= 0.0f) continue;
        joint_.push_back(model.skin_joints[v][k]);
        weight_.push_back(w[k] / sum);
      }
    }
  }
}

}  // namespace sweepd::deform
