// SkinningTable: a model's skin influences laid out for the skinning baselines (LBS, DQS), built
// once per model (ModelRuntime) as the fastest skinning libraries lay them out (ozz-animation's
// SkinningJob runs one loop per influence count): vertices grouped by how many joints move them
// (1 to kInfluences; zero weights dropped), each group a loop without branches; weights divided
// by their sum here, not per frame; rest positions and normals copied beside them, so a loop
// reads its items in order. A vertex with no positive weight (no file we load has one) is a
// group of its own that stays at rest.
//
// Items of one group are consecutive and in vertex order; item i moves vertex vertex(i). Each
// group is padded to a multiple of kSkinningChunk items with copies of its last item, so a loop
// that handles kSkinningChunk items at once (DQS on AVX2) never meets a partial chunk; a copy
// writes the same vertex with the same value, from the same block (vertex_blocks.h's granule).
// The loops run on SSE2 (any x86-64, or generic vector code elsewhere) or, where the CPU has them,
// AVX2 with FMA (results differ by rounding); each item is computed by the same code whatever
// range it falls in, so results do not depend on how items are split between threads.
#pragma once

#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "deform/model/model.h"
#include "deform/posing/sweep_vertex_kinds.h"

namespace sweepd::deform {

inline constexpr std::size_t kSkinningChunk = 8;

class SkinningTable {
 public:
  // Throws std::invalid_argument on a model whose skin arrays do not match its vertices, or
  // kAvx2Fma on a CPU without them.
  explicit SkinningTable(const Model& model,
                         VertexLoopInstructions instructions = widest_vertex_loop_instructions());

  struct Group {
    int influences;               // 0 to kInfluences joints per item
    std::size_t begin, end;       // items
    std::size_t first_influence;  // index into joints()/weights() of item `begin`'s first
  };

  VertexLoopInstructions instructions() const { return instructions_; }
  std::size_t vertex_count() const { return vertex_count_; }  // the model's
  std::size_t item_count() const { return vertex_.size(); }   // with the padding
  std::size_t joint_count() const { return joint_count_; }
  std::span<const Group> groups() const { return groups_; }
  std::span<const std::uint32_t> vertices() const { return vertex_; }
  std::span<const glm::vec4> rest_positions() const { return rest_position_; }  // (p, 1)
  std::span<const glm::vec4> rest_normals() const { return rest_normal_; }      // (n, 0)
  std::span<const std::uint32_t> joints() const { return joint_; }              // per influence
  std::span<const float> weights() const { return weight_; }                    // per influence

 private:
  VertexLoopInstructions instructions_;
  std::size_t vertex_count_, joint_count_;
  std::vector<Group> groups_;
  std::vector<std::uint32_t> vertex_;
  std::vector<glm::vec4> rest_position_, rest_normal_;
  std::vector<std::uint32_t> joint_;
  std::vector<float> weight_;
};

}  // namespace sweepd::deform
