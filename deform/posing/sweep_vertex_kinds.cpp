#include "deform/posing/sweep_vertex_kinds.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>

#include "deform/binding/bound_model.h"
#include "deform/posing/single_term_batches.h"
#include "deform/simd/float_lanes.h"

namespace sweepd::deform {

namespace {

constexpr int kTermKinds = kSweepsPerVertex + 1;  // 0 to kSweepsPerVertex terms
static_assert(SweepVertexKinds::kItemGranule == SingleTermBatches::kLanes);

struct ItemData {
  const std::uint32_t* vertex;
  const glm::vec4* scaled_rest;
  const std::uint32_t* joint;
  const SweepTerm* term;
};

struct TermRows {
  const float* first;  // the term's first row (aligned); the second follows it
  float x, y;          // the cross-section point's coordinates in the rows' frame
};

[[gnu::always_inline]] inline TermRows term_rows(const SweepTerm& term, const SweepSample* table) {
  const float* s0 = static_cast<const float*>(
      __builtin_assume_aligned(&table[term.row].centre.x, alignof(SweepSample)));
  const float a = s0[3] + term.fraction * s0[11];
  const float b = s0[7] + term.fraction * s0[15];
  return {s0, a * term.cos_theta + term.x_shift, b * term.sin_theta + term.y_shift};
}

// Items [0, count) of one kind: kJoints skinned joints and kTerms sweep terms each, 4 lanes
// (SSE2, NEON).
template <int kJoints, int kTerms>
void evaluate_kind(ItemData d, std::size_t count, const SweepSample* table,
                   const glm::mat4* skinning, glm::vec3* positions) {
  for (std::size_t i = 0; i < count; ++i) {
    FloatLanes p = {0.0f, 0.0f, 0.0f, 0.0f};
    for (int k = 0; k < kJoints; ++k, ++d.scaled_rest, ++d.joint) {
      const float* m = &skinning[*d.joint][0][0];
      const glm::vec4& s = *d.scaled_rest;
      p += load_lanes(m) * s.x + load_lanes(m + 4) * s.y + load_lanes(m + 8) * s.z +
           load_lanes(m + 12) * s.w;
    }
    for (int t = 0; t < kTerms; ++t, ++d.term) {
      const SweepTerm& term = *d.term;
      const auto [s0, x, y] = term_rows(term, table);
      const float* s1 = s0 + 16;
      const FloatLanes at0 = load_lanes(s0) + load_lanes(s0 + 4) * x + load_lanes(s0 + 8) * y +
                             load_lanes(s0 + 12) * term.c;
      const FloatLanes at1 = load_lanes(s1) + load_lanes(s1 + 4) * x + load_lanes(s1 + 8) * y +
                             load_lanes(s1 + 12) * term.c;
      p += at0 * term.weight_below + at1 * term.weight_above;
    }
    positions[d.vertex[i]] = glm::vec3(p[0], p[1], p[2]);
  }
}

#if defined(__x86_64__)
// The same with 8 lanes (AVX2, FMA). They hold two partial sums of the position (lanes 0-3 and
// 4-7): a matrix's columns 0|1 and 2|3, a term's rows row|row + 1; added once per vertex.
template <int kJoints, int kTerms>
[[gnu::target("avx2,fma")]] void evaluate_kind_avx2(ItemData d, std::size_t count,
                                                    const SweepSample* table,
                                                    const glm::mat4* skinning,
                                                    glm::vec3* positions) {
  for (std::size_t i = 0; i < count; ++i) {
    FloatLanes8 p = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f};
    for (int k = 0; k < kJoints; ++k, ++d.scaled_rest, ++d.joint) {
      const float* m = &skinning[*d.joint][0][0];
      FloatLanes8 columns01, columns23;
      std::memcpy(&columns01, m, sizeof(columns01));
      std::memcpy(&columns23, m + 8, sizeof(columns23));
      const FloatLanes s = load_lanes(&d.scaled_rest->x);
      p += columns01 * __builtin_shufflevector(s, s, 0, 0, 0, 0, 1, 1, 1, 1) +
           columns23 * __builtin_shufflevector(s, s, 2, 2, 2, 2, 3, 3, 3, 3);
    }
    for (int t = 0; t < kTerms; ++t, ++d.term) {
      const SweepTerm& term = *d.term;
      const auto [s0, x, y] = term_rows(term, table);
      const float* s1 = s0 + 16;
      const FloatLanes weights = {term.weight_below, term.weight_above, 0.0f, 0.0f};
      const FloatLanes8 centres =
          __builtin_shufflevector(load_lanes(s0), load_lanes(s1), 0, 1, 2, 3, 4, 5, 6, 7);
      const FloatLanes8 x_axes =
          __builtin_shufflevector(load_lanes(s0 + 4), load_lanes(s1 + 4), 0, 1, 2, 3, 4, 5, 6, 7);
      const FloatLanes8 y_axes =
          __builtin_shufflevector(load_lanes(s0 + 8), load_lanes(s1 + 8), 0, 1, 2, 3, 4, 5, 6, 7);
      const FloatLanes8 normals =
          __builtin_shufflevector(load_lanes(s0 + 12), load_lanes(s1 + 12), 0, 1, 2, 3, 4, 5, 6, 7);
      p += (centres + x_axes * x + y_axes * y + normals * term.c) *
           __builtin_shufflevector(weights, weights, 0, 0, 0, 0, 1, 1, 1, 1);
    }
    const FloatLanes sum =
        __builtin_shufflevector(p, p, 0, 1, 2, 3) + __builtin_shufflevector(p, p, 4, 5, 6, 7);
    positions[d.vertex[i]] = glm::vec3(sum[0], sum[1], sum[2]);
  }
}

#endif

using KindLoop = void (*)(ItemData, std::size_t, const SweepSample*, const glm::mat4*, glm::vec3*);

// Indexed by influences * kTermKinds + terms.
using KindLoops = std::array<KindLoop, (kInfluences + 1) * kTermKinds>;

template <int... kKind>
constexpr KindLoops baseline_loops(std::integer_sequence<int, kKind...>) {
  return {&evaluate_kind<kKind / kTermKinds, kKind % kTermKinds>...};
}
constexpr KindLoops kBaselineLoops =
    baseline_loops(std::make_integer_sequence<int, (kInfluences + 1) * kTermKinds>());

#if defined(__x86_64__)
template <int... kKind>
constexpr KindLoops avx2_loops(std::integer_sequence<int, kKind...>) {
  return {&evaluate_kind_avx2<kKind / kTermKinds, kKind % kTermKinds>...};
}
constexpr KindLoops kAvx2Loops =
    avx2_loops(std::make_integer_sequence<int, (kInfluences + 1) * kTermKinds>());
#endif

const KindLoops& loops_for(VertexLoopInstructions instructions) {
#if defined(__x86_64__)
  if (instructions == VertexLoopInstructions::kAvx2Fma) return kAvx2Loops;
#endif
  (void)instructions;
  return kBaselineLoops;
}

}  // namespace

VertexLoopInstructions widest_vertex_loop_instructions() {
#if defined(__x86_64__)
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"))
    return VertexLoopInstructions::kAvx2Fma;
#endif
  return VertexLoopInstructions::kBaseline;
}

SweepVertexKinds::SweepVertexKinds(const Model& model, std::span<const float> skin_share,
                                   std::span<const std::uint32_t> first_term,
                                   std::span<const SweepTerm> terms,
                                   VertexLoopInstructions instructions)
    : SweepVertexKinds(model, model.skin_joints, model.skin_weights, skin_share, first_term, terms,
                       instructions) {}

SweepVertexKinds::SweepVertexKinds(
    const Model& model, std::span<const std::array<std::uint16_t, kInfluences>> skin_joints,
    std::span<const std::array<float, kInfluences>> skin_weights, std::span<const float> skin_share,
    std::span<const std::uint32_t> first_term, std::span<const SweepTerm> terms,
    VertexLoopInstructions instructions)
    : instructions_(instructions) {
  if (instructions == VertexLoopInstructions::kAvx2Fma &&
      widest_vertex_loop_instructions() != VertexLoopInstructions::kAvx2Fma)
    throw std::invalid_argument("sweep vertex kinds: this CPU has no AVX2 with FMA");
  const std::size_t n = model.vertex_count();
  if (skin_share.size() != n || first_term.size() != n + 1)
    throw std::invalid_argument("sweep vertex kinds: " + std::to_string(skin_share.size()) +
                                " skin shares and " + std::to_string(first_term.size()) +
                                " term offsets for " + std::to_string(n) + " vertices");
  if (skin_joints.size() != n || skin_weights.size() != n)
    throw std::invalid_argument("sweep vertex kinds: " + std::to_string(skin_joints.size()) +
                                " skin joint and " + std::to_string(skin_weights.size()) +
                                " skin weight sets for " + std::to_string(n) + " vertices");
  const auto influences_of = [&](std::size_t v) {
    int count = 0;
    if (skin_share[v] > 0.0f)
      for (int k = 0; k < kInfluences; ++k) count += skin_weights[v][k] > 0.0f;
    return count;
  };
  std::vector<std::vector<std::uint32_t>> by_kind((kInfluences + 1) * kTermKinds);
  for (std::size_t v = 0; v < n; ++v) {
    const std::size_t term_count = first_term[v + 1] - first_term[v];
    if (term_count > static_cast<std::size_t>(kSweepsPerVertex))
      throw std::invalid_argument("sweep vertex kinds: vertex " + std::to_string(v) + " has " +
                                  std::to_string(term_count) + " sweep terms");
    by_kind[influences_of(v) * kTermKinds + term_count].push_back(static_cast<std::uint32_t>(v));
  }
  // One term, no skinned share: batches.
  std::vector<std::uint32_t>& single = by_kind[0 * kTermKinds + 1];
  std::vector<SweepTerm> single_terms;
  for (const std::uint32_t v : single) single_terms.push_back(terms[first_term[v]]);
  single_term_ = std::make_shared<const SingleTermBatches>(single, single_terms, instructions);
  single_term_items_ = single_term_->item_count();
  single.clear();
  for (std::size_t k = 0; k < by_kind.size(); ++k) {
    if (by_kind[k].empty()) continue;
    kinds_.push_back({static_cast<int>(k) / kTermKinds, static_cast<int>(k) % kTermKinds,
                      vertex_.size(), vertex_.size() + by_kind[k].size(), scaled_rest_.size(),
                      terms_.size()});
    for (const std::uint32_t v : by_kind[k]) {
      vertex_.push_back(v);
      if (kinds_.back().influences > 0)
        for (int j = 0; j < kInfluences; ++j) {
          const float w = skin_weights[v][j];
          if (w <= 0.0f) continue;
          scaled_rest_.push_back(skin_share[v] * w * glm::vec4(model.positions[v], 1.0f));
          joint_.push_back(static_cast<std::uint32_t>(skin_joints[v][j]));
        }
      terms_.insert(terms_.end(), terms.begin() + first_term[v], terms.begin() + first_term[v + 1]);
    }
  }
}

void SweepVertexKinds::evaluate(std::span<const SweepSample> table,
                                std::span<const glm::mat4> skinning, std::span<glm::vec3> positions,
                                std::size_t begin, std::size_t end) const {
  single_term_->evaluate(table, positions, begin, std::min(end, single_term_items_));
  begin = std::max(begin, single_term_items_) - single_term_items_;
  end = std::max(end, single_term_items_) - single_term_items_;
  const KindLoops& loops = loops_for(instructions_);
  for (const Kind& kind : kinds_) {
    const std::size_t from = std::max(begin, kind.begin), to = std::min(end, kind.end);
    if (from >= to) continue;
    const std::size_t skipped = from - kind.begin;
    const ItemData data{vertex_.data() + from,
                        scaled_rest_.data() + kind.first_influence + skipped * kind.influences,
                        joint_.data() + kind.first_influence + skipped * kind.influences,
                        terms_.data() + kind.first_term + skipped * kind.terms};
    loops[kind.influences * kTermKinds + kind.terms](data, to - from, table.data(), skinning.data(),
                                                     positions.data());
  }
}

}  // namespace sweepd::deform
