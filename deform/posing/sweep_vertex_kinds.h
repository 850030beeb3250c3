// SweepVertexKinds: the sweep fast path's per-vertex data, grouped by kind so that each group
// runs a loop without branches (SweepPoser::deform).
//
// A vertex's kind is (skin influences, sweep terms): how many joints its skinned share follows
// (0 to kInfluences; 0 when it has no skinned share) and how many sweeps it is bound to (0 to
// kSweepsPerVertex). Vertices of one kind are consecutive items, in vertex order within a kind;
// item i moves vertex vertex[i]. A kind's influences and terms are stored item by item, so the
// loop walks them in order:
//   skinned share  Σ_j M_j (s w_j p, s w_j)   (s: skin share, w_j: skin weight, p: rest position)
//   sweep term     g0 · at(row) + g1 · at(row + 1), at(r) = C_r + x X_r + y Y_r + c N_r,
//                  x = a(f) cos θ + da cos θ, y = b(f) sin θ + db sin θ, a(f) = a + f a_step
//                  and b(f) likewise (the rows interpolated at the fraction f); g0 = w (1 - f),
//                  g1 = w f.
// The loops run on SSE2 (any x86-64, or the generic vector code elsewhere) or, where the CPU
// has them, AVX2 with FMA (8 lanes, fused multiply-adds: the results differ by rounding).
// The vertices with one sweep term and no skinned share come first, eight at a time
// (SingleTermBatches, single_term_batches.h: items padded to whole batches), then the other kinds.
// evaluate() computes items [begin, end) from the per-frame table (SweepSample rows) and the
// skinning matrices; begin is a multiple of kItemGranule (a batch is never split); each vertex
// is computed by the same code whatever the range, so results do not depend on how the items
// are split between threads.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <span>
#include <vector>

#include "deform/model/model.h"

namespace sweepd::deform {

// One row of the per-frame table: a sweep at one sample, 16 floats (one cache line). The steps
// are the next row's a and b minus this row's (meaningless on a sweep's last row, where no term
// starts).
struct alignas(64) SweepSample {
  glm::vec3 centre;
  float a;
  glm::vec3 x_axis;
  float b;
  glm::vec3 y_axis;
  float a_step;
  glm::vec3 normal;
  float b_step;
};

// One (vertex, sweep) term; see the header comment.
struct SweepTerm {
  std::uint32_t row;  // the table row at or below the vertex's t; the term also reads row + 1
  float fraction;     // f: between row and row + 1
  float weight_below, weight_above;  // g0 = w (1 - f), g1 = w f
  float cos_theta, sin_theta;
  float x_shift, y_shift;  // da cos θ, db sin θ
  float c;                 // offset along the sweep's normal
};

enum class VertexLoopInstructions { kBaseline, kAvx2Fma };
// kAvx2Fma on an x86-64 CPU that has AVX2 and FMA, else kBaseline.
VertexLoopInstructions widest_vertex_loop_instructions();

class SingleTermBatches;

class SweepVertexKinds {
 public:
  static constexpr std::size_t kItemGranule = 8;  // SingleTermBatches::kLanes

  // skin_share: per vertex, the share that follows LBS; terms of vertex v:
  // terms[first_term[v], first_term[v + 1]), at most kSweepsPerVertex. Throws for more terms,
  // mismatched sizes, or kAvx2Fma on a CPU without them.
  SweepVertexKinds(const Model& model, std::span<const float> skin_share,
                   std::span<const std::uint32_t> first_term, std::span<const SweepTerm> terms,
                   VertexLoopInstructions instructions = widest_vertex_loop_instructions());
  // The same with the skinned share following skin_joints / skin_weights (one per vertex)
  // instead of the model's own weights (BoundModel::skinned_share_weights).
  SweepVertexKinds(const Model& model,
                   std::span<const std::array<std::uint16_t, kInfluences>> skin_joints,
                   std::span<const std::array<float, kInfluences>> skin_weights,
                   std::span<const float> skin_share, std::span<const std::uint32_t> first_term,
                   std::span<const SweepTerm> terms,
                   VertexLoopInstructions instructions = widest_vertex_loop_instructions());

  std::size_t item_count() const { return single_term_items_ + vertex_.size(); }

  // Writes positions[vertex[i]] for the items i in [begin, end).
  void evaluate(std::span<const SweepSample> table, std::span<const glm::mat4> skinning,
                std::span<glm::vec3> positions, std::size_t begin, std::size_t end) const;

 private:
  struct Kind {
    int influences, terms;
    std::size_t begin, end;  // items
    std::size_t first_influence, first_term;
  };

  VertexLoopInstructions instructions_;
  std::shared_ptr<const SingleTermBatches> single_term_;  // items [0, single_term_items_)
  std::size_t single_term_items_ = 0;
  std::vector<Kind> kinds_;  // items from single_term_items_ on
  std::vector<std::uint32_t> vertex_;   // per item
  std::vector<glm::vec4> scaled_rest_;  // per influence: s w_j (p, 1)
  std::vector<std::uint32_t> joint_;    // per influence
  std::vector<SweepTerm> terms_;        // per term, item by item
};

}  // namespace sweepd::deform
