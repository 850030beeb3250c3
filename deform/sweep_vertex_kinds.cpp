#include "deform/sweep_vertex_kinds.h"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>
#include <utility>

#include "deform/bound_model.h"
#include "deform/float_lanes.h"

namespace sweepd::deform {

namespace {

constexpr int kTermKinds = kSweepsPerVertex + 1;  // 0 to kSweepsPerVertex terms

struct ItemData {
  const std::uint32_t* vertex;
  const glm::vec4* scaled_rest;
  const std::uint32_t* joint;
  const SweepTerm* term;
};

// Items [0, count) of one kind: kJoints skinned joints and kTerms sweep terms each.
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
      const float* s0 = &table[term.row].centre.x;
      const float* s1 = s0 + 16;
      const float a = s0[3] + term.fraction * (s1[3] - s0[3]);
      const float b = s0[7] + term.fraction * (s1[7] - s0[7]);
      const float x = a * term.cos_theta + term.x_shift;
      const float y = b * term.sin_theta + term.y_shift;
      const FloatLanes at0 = load_lanes(s0) + load_lanes(s0 + 4) * x + load_lanes(s0 + 8) * y +
                             load_lanes(s0 + 12) * term.c;
      const FloatLanes at1 = load_lanes(s1) + load_lanes(s1 + 4) * x + load_lanes(s1 + 8) * y +
                             load_lanes(s1 + 12) * term.c;
      p += at0 * term.weight_below + at1 * term.weight_above;
    }
    positions[d.vertex[i]] = glm::vec3(p[0], p[1], p[2]);
  }
}

using KindLoop = void (*)(ItemData, std::size_t, const SweepSample*, const glm::mat4*, glm::vec3*);

template <int... kKind>
constexpr std::array<KindLoop, sizeof...(kKind)> kind_loops(std::integer_sequence<int, kKind...>) {
  return {&evaluate_kind<kKind / kTermKinds, kKind % kTermKinds>...};
}

// Indexed by influences * kTermKinds + terms.
constexpr auto kKindLoops =
    kind_loops(std::make_integer_sequence<int, (kInfluences + 1) * kTermKinds>());

}  // namespace

SweepVertexKinds::SweepVertexKinds(const Model& model, std::span<const float> skin_share,
                                   std::span<const std::uint32_t> first_term,
                                   std::span<const SweepTerm> terms) {
  const std::size_t n = model.vertex_count();
  if (skin_share.size() != n || first_term.size() != n + 1)
    throw std::invalid_argument("sweep vertex kinds: " + std::to_string(skin_share.size()) +
                                " skin shares and " + std::to_string(first_term.size()) +
                                " term offsets for " + std::to_string(n) + " vertices");
  const auto influences_of = [&](std::size_t v) {
    int count = 0;
    if (skin_share[v] > 0.0f)
      for (int k = 0; k < kInfluences; ++k) count += model.skin_weights[v][k] > 0.0f;
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
  for (std::size_t k = 0; k < by_kind.size(); ++k) {
    if (by_kind[k].empty()) continue;
    kinds_.push_back({static_cast<int>(k) / kTermKinds, static_cast<int>(k) % kTermKinds,
                      vertex_.size(), vertex_.size() + by_kind[k].size(), scaled_rest_.size(),
                      terms_.size()});
    for (const std::uint32_t v : by_kind[k]) {
      vertex_.push_back(v);
      if (kinds_.back().influences > 0)
        for (int j = 0; j < kInfluences; ++j) {
          const float w = model.skin_weights[v][j];
          if (w <= 0.0f) continue;
          scaled_rest_.push_back(skin_share[v] * w * glm::vec4(model.positions[v], 1.0f));
          joint_.push_back(static_cast<std::uint32_t>(model.skin_joints[v][j]));
        }
      terms_.insert(terms_.end(), terms.begin() + first_term[v], terms.begin() + first_term[v + 1]);
    }
  }
}

void SweepVertexKinds::evaluate(std::span<const SweepSample> table,
                                std::span<const glm::mat4> skinning, std::span<glm::vec3> positions,
                                std::size_t begin, std::size_t end) const {
  for (const Kind& kind : kinds_) {
    const std::size_t from = std::max(begin, kind.begin), to = std::min(end, kind.end);
    if (from >= to) continue;
    const std::size_t skipped = from - kind.begin;
    const ItemData data{vertex_.data() + from,
                        scaled_rest_.data() + kind.first_influence + skipped * kind.influences,
                        joint_.data() + kind.first_influence + skipped * kind.influences,
                        terms_.data() + kind.first_term + skipped * kind.terms};
    kKindLoops[kind.influences * kTermKinds + kind.terms](data, to - from, table.data(),
                                                          skinning.data(), positions.data());
  }
}

}  // namespace sweepd::deform
