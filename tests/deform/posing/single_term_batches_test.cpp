// SingleTermBatches on a hand-made three-row table: 19 single-term vertices given out of row
// order over two row pairs (so batches are sorted, split by row and padded), evaluated in two
// ranges split at a batch boundary, for every instruction set the CPU has, against the term
// written out with glm.
#include "deform/posing/single_term_batches.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "tests/deform/posing/hand_made_table.h"

namespace sweepd::deform {
namespace {

TEST(SingleTermBatches, SortsPadsAndEvaluatesEveryVertexAsWrittenOut) {
  const std::vector<SweepSample> table = test::hand_made_table(3);
  std::vector<std::uint32_t> vertices;
  std::vector<SweepTerm> terms;
  std::vector<glm::vec3> expected;
  for (std::uint32_t v = 0; v < 19; ++v) {
    const std::uint32_t row = v % 3 == 0 ? 1 : 0;  // 7 on rows 1-2, 12 on rows 0-1, interleaved
    const float fraction = 0.05f * static_cast<float>(v), weight = 1.0f - 0.01f * v;
    const float theta = 0.33f * static_cast<float>(v), da = 0.001f * v, db = -0.002f * v;
    const float c = 0.0005f * static_cast<float>(v % 5);
    const SweepTerm term = test::make_term(row, fraction, weight, theta, da, db, c);
    vertices.push_back(v);
    terms.push_back(term);
    const float a = glm::mix(table[row].a, table[row + 1].a, fraction) + da;
    const float b = glm::mix(table[row].b, table[row + 1].b, fraction) + db;
    glm::vec3 at[2];
    for (int r = 0; r < 2; ++r)
      at[r] = table[row + r].centre + a * std::cos(theta) * table[row + r].x_axis +
              b * std::sin(theta) * table[row + r].y_axis + c * table[row + r].normal;
    expected.push_back(weight * glm::mix(at[0], at[1], fraction));
  }
  std::vector<VertexLoopInstructions> sets = {VertexLoopInstructions::kBaseline};
  if (widest_vertex_loop_instructions() != VertexLoopInstructions::kBaseline)
    sets.push_back(widest_vertex_loop_instructions());
  for (const VertexLoopInstructions set : sets) {
    const SingleTermBatches batches(vertices, terms, set);
    // Rows 0-1: 12 vertices, two batches (4 lanes padded); rows 1-2: 7, one batch (1 padded).
    ASSERT_EQ(batches.item_count(), 3 * SingleTermBatches::kLanes);
    std::vector<glm::vec3> positions(vertices.size(), glm::vec3(9.0f));
    batches.evaluate(table, positions, 0, SingleTermBatches::kLanes);
    batches.evaluate(table, positions, SingleTermBatches::kLanes, batches.item_count());
    for (std::size_t v = 0; v < vertices.size(); ++v)  // float rounding of values near 1
      EXPECT_LE(glm::length(positions[v] - expected[v]), 1e-6f)
          << "vertex " << v << ", instruction set " << static_cast<int>(set);
  }
}

}  // namespace
}  // namespace sweepd::deform
