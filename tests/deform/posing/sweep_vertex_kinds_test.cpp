// SweepVertexKinds on a hand-made two-row table: a sweep term, a skinned share blended with a
// term, a vertex with neither, for every instruction set the CPU has, against the formulas
// written out with glm; and the inputs it refuses.
#include "deform/posing/sweep_vertex_kinds.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <stdexcept>
#include <vector>

#include "deform/binding/bound_model.h"
#include "tests/deform/posing/hand_made_table.h"

namespace sweepd::deform {
namespace {

// The term written out: each row's point at the interpolated half-axes, then the rows blended.
glm::vec3 expected_term(const std::vector<SweepSample>& table, float fraction, float weight,
                        float theta, float da, float db, float c) {
  const float a = glm::mix(table[0].a, table[1].a, fraction) + da;
  const float b = glm::mix(table[0].b, table[1].b, fraction) + db;
  glm::vec3 at[2];
  for (int r = 0; r < 2; ++r)
    at[r] = table[r].centre + a * std::cos(theta) * table[r].x_axis +
            b * std::sin(theta) * table[r].y_axis + c * table[r].normal;
  return weight * glm::mix(at[0], at[1], fraction);
}

Model three_vertices() {
  Model model;
  model.positions = {{0.2f, 1.1f, 0.0f}, {0.3f, 0.9f, 0.1f}, {0.0f, 0.0f, 0.0f}};
  model.skin_joints = {{{0, 1, 0, 0}}, {{0, 1, 0, 0}}, {{0, 0, 0, 0}}};
  model.skin_weights = {{{1, 0, 0, 0}}, {{0.7f, 0.3f, 0, 0}}, {{1, 0, 0, 0}}};
  return model;
}

TEST(SweepVertexKinds, EvaluatesTermsAndSkinnedSharesAsWrittenOut) {
  const Model model = three_vertices();
  const std::vector<SweepSample> table = test::hand_made_table(2);
  const std::vector<glm::mat4> skinning = {
      glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.1f, 0.0f)),
      glm::rotate(glm::mat4(1.0f), 0.4f, glm::vec3(1, 0, 0))};
  // Vertex 0: one term only; vertex 1: half skinned, half the term; vertex 2: nothing.
  const std::vector<float> skin_share = {0.0f, 0.5f, 0.0f};
  const std::vector<std::uint32_t> first_term = {0, 1, 2, 2};
  const std::vector<SweepTerm> terms = {
      test::make_term(0, 0.25f, 1.0f, 0.7f, 0.01f, -0.02f, 0.003f),
      test::make_term(0, 0.6f, 0.5f, 2.5f, 0.0f, 0.01f, -0.002f)};
  const glm::vec3 lbs1 =
      glm::vec3((0.7f * skinning[0] + 0.3f * skinning[1]) * glm::vec4(model.positions[1], 1.0f));
  const glm::vec3 expected[3] = {
      expected_term(table, 0.25f, 1.0f, 0.7f, 0.01f, -0.02f, 0.003f),
      0.5f * lbs1 + expected_term(table, 0.6f, 0.5f, 2.5f, 0.0f, 0.01f, -0.002f), glm::vec3(0.0f)};
  std::vector<VertexLoopInstructions> sets = {VertexLoopInstructions::kBaseline};
  if (widest_vertex_loop_instructions() != VertexLoopInstructions::kBaseline)
    sets.push_back(widest_vertex_loop_instructions());
  for (const VertexLoopInstructions set : sets) {
    const SweepVertexKinds kinds(model, skin_share, first_term, terms, set);
    // Vertex 0 fills a batch of single-term items (its copies in the unused lanes), vertex 1's
    // term a batch of term points; vertices 1 and 2 are one junction item each.
    ASSERT_EQ(kinds.batch_item_count(), 2 * SweepVertexKinds::kItemGranule);
    ASSERT_EQ(kinds.junction_count(), 2u);
    ASSERT_EQ(kinds.term_lane_count(), 3 * SweepVertexKinds::kItemGranule);  // one batch
    std::vector<glm::vec3> positions(3, glm::vec3(9.0f));
    std::vector<float> term_lanes(kinds.term_lane_count());
    kinds.evaluate(table, skinning, term_lanes, positions);
    for (int v = 0; v < 3; ++v)  // float rounding of values near 1: a few 1e-7
      EXPECT_LE(glm::length(positions[v] - expected[v]), 1e-6f)
          << "vertex " << v << ", instruction set " << static_cast<int>(set);
  }
}

TEST(SweepVertexKinds, RefusesMismatchedSizesAndTooManyTerms) {
  const Model model = three_vertices();
  const std::vector<SweepTerm> terms(4, test::make_term(0, 0.5f, 0.25f, 0.0f, 0.0f, 0.0f, 0.0f));
  EXPECT_THROW(SweepVertexKinds(model, std::vector<float>(2), std::vector<std::uint32_t>(4), terms),
               std::invalid_argument);
  EXPECT_THROW(SweepVertexKinds(model, std::vector<float>(3), std::vector<std::uint32_t>(3), terms),
               std::invalid_argument);
  // Four terms on vertex 0: more sweeps than a vertex can be bound to.
  static_assert(kSweepsPerVertex == 3);
  EXPECT_THROW(
      SweepVertexKinds(model, std::vector<float>(3), std::vector<std::uint32_t>{0, 4, 4, 4}, terms),
      std::invalid_argument);
}

}  // namespace
}  // namespace sweepd::deform
