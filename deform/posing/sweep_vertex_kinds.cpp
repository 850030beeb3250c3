#include "deform/posing/sweep_vertex_kinds.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <numeric>
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
  const std::uint32_t* term_lane;  // per term: where its point's x lies in the term lanes
};

// A term's point from the term lanes (SingleTermBatches::evaluate_lane_by_lane).
inline FloatLanes term_point(const float* term_lanes, std::uint32_t lane) {
  const float* x = term_lanes + lane;
  constexpr std::size_t kLanes = SingleTermBatches::kLanes;
  return FloatLanes{x[0], x[kLanes], x[2 * kLanes], 0.0f};
}

// Items [0, count) of one kind: kJoints skinned joints and kTerms sweep terms each, 4 lanes
// (SSE2, NEON). A term's point (weighted, both rows) is already in the term lanes.
template <int kJoints, int kTerms>
void evaluate_kind(ItemData d, std::size_t count, const float* term_lanes,
                   const glm::mat4* skinning, glm::vec3* positions) {
  for (std::size_t i = 0; i < count; ++i) {
    FloatLanes p = {0.0f, 0.0f, 0.0f, 0.0f};
    for (int k = 0; k < kJoints; ++k, ++d.scaled_rest, ++d.joint) {
      const float* m = &skinning[*d.joint][0][0];
      const glm::vec4& s = *d.scaled_rest;
      p += load_lanes(m) * s.x + load_lanes(m + 4) * s.y + load_lanes(m + 8) * s.z +
           load_lanes(m + 12) * s.w;
    }
    for (int t = 0; t < kTerms; ++t, ++d.term_lane) p += term_point(term_lanes, *d.term_lane);
    positions[d.vertex[i]] = glm::vec3(p[0], p[1], p[2]);
  }
}

#if defined(__x86_64__)
// The same with 8 lanes (AVX2, FMA) for the skinned share: they hold two partial sums of the
// position (lanes 0-3 and 4-7: a matrix's columns 0|1 and 2|3), added once per vertex.
template <int kJoints, int kTerms>
[[gnu::target("avx2,fma")]] void evaluate_kind_avx2(ItemData d, std::size_t count,
                                                    const float* term_lanes,
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
    FloatLanes sum =
        __builtin_shufflevector(p, p, 0, 1, 2, 3) + __builtin_shufflevector(p, p, 4, 5, 6, 7);
    for (int t = 0; t < kTerms; ++t, ++d.term_lane) sum += term_point(term_lanes, *d.term_lane);
    positions[d.vertex[i]] = glm::vec3(sum[0], sum[1], sum[2]);
  }
}

#endif

using KindLoop = void (*)(ItemData, std::size_t, const float*, const glm::mat4*, glm::vec3*);

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
  single.clear();
  std::vector<SweepTerm> junction_terms;  // item by item
  for (std::size_t k = 0; k < by_kind.size(); ++k) {
    if (by_kind[k].empty()) continue;
    kinds_.push_back({static_cast<int>(k) / kTermKinds, static_cast<int>(k) % kTermKinds,
                      vertex_.size(), vertex_.size() + by_kind[k].size(), scaled_rest_.size(),
                      junction_terms.size()});
    for (const std::uint32_t v : by_kind[k]) {
      vertex_.push_back(v);
      if (kinds_.back().influences > 0)
        for (int j = 0; j < kInfluences; ++j) {
          const float w = skin_weights[v][j];
          if (w <= 0.0f) continue;
          scaled_rest_.push_back(skin_share[v] * w * glm::vec4(model.positions[v], 1.0f));
          joint_.push_back(static_cast<std::uint32_t>(skin_joints[v][j]));
        }
      junction_terms.insert(junction_terms.end(), terms.begin() + first_term[v],
                            terms.begin() + first_term[v + 1]);
    }
  }
  // The junctions' terms in batches too, their points written lane by lane (whole batches at
  // once); term_lane_ says where each term's point lies.
  std::vector<std::uint32_t> term_index(junction_terms.size());
  std::iota(term_index.begin(), term_index.end(), std::uint32_t{0});
  junction_terms_ =
      std::make_shared<const SingleTermBatches>(term_index, junction_terms, instructions);
  term_lane_ = junction_terms_->lane_offsets(junction_terms.size());
}

std::size_t SweepVertexKinds::term_lane_count() const { return 3 * junction_terms_->item_count(); }

std::size_t SweepVertexKinds::batch_item_count() const {
  return single_term_->item_count() + junction_terms_->item_count();
}

void SweepVertexKinds::evaluate_batches(std::span<const SweepSample> table,
                                        std::span<glm::vec3> positions, std::span<float> term_lanes,
                                        std::size_t begin, std::size_t end) const {
  const std::size_t single_items = single_term_->item_count();
  single_term_->evaluate(table, positions, begin, std::min(end, single_items));
  junction_terms_->evaluate_lane_by_lane(table, term_lanes,
                                         std::max(begin, single_items) - single_items,
                                         std::max(end, single_items) - single_items);
}

void SweepVertexKinds::evaluate_junctions(std::span<const glm::mat4> skinning,
                                          std::span<const float> term_lanes,
                                          std::span<glm::vec3> positions, std::size_t begin,
                                          std::size_t end) const {
  const KindLoops& loops = loops_for(instructions_);
  for (const Kind& kind : kinds_) {
    const std::size_t from = std::max(begin, kind.begin), to = std::min(end, kind.end);
    if (from >= to) continue;
    const std::size_t skipped = from - kind.begin;
    const ItemData data{vertex_.data() + from,
                        scaled_rest_.data() + kind.first_influence + skipped * kind.influences,
                        joint_.data() + kind.first_influence + skipped * kind.influences,
                        term_lane_.data() + kind.first_term + skipped * kind.terms};
    loops[kind.influences * kTermKinds + kind.terms](data, to - from, term_lanes.data(),
                                                     skinning.data(), positions.data());
  }
}

void SweepVertexKinds::evaluate(std::span<const SweepSample> table,
                                std::span<const glm::mat4> skinning, std::span<float> term_lanes,
                                std::span<glm::vec3> positions) const {
  evaluate_batches(table, positions, term_lanes, 0, batch_item_count());
  evaluate_junctions(skinning, term_lanes, positions, 0, junction_count());
}

}  // namespace sweepd::deform
