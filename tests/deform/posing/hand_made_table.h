// A hand-made per-frame sample table for the vertex-loop tests: `rows` rows of one sweep, frames
// turned by 0.1 rad about z from row to row, the centre rising, a and b growing, the steps set;
// and a sweep term on it, written out from its parameters.
#pragma once

#include <cmath>
#include <cstdint>
#include <glm/gtc/matrix_transform.hpp>
#include <vector>

#include "deform/posing/sweep_vertex_kinds.h"

namespace sweepd::deform::test {

inline std::vector<SweepSample> hand_made_table(int rows) {
  std::vector<SweepSample> table(rows);
  for (int r = 0; r < rows; ++r) {
    const glm::mat3 frame = glm::mat3(glm::rotate(glm::mat4(1.0f), 0.1f * r, glm::vec3(0, 0, 1)));
    table[r].centre = glm::vec3(0.1f, 1.0f + 0.2f * r, -0.3f);
    table[r].x_axis = frame[0];
    table[r].y_axis = frame[1];
    table[r].normal = frame[2];
    table[r].a = 0.05f + 0.01f * r;
    table[r].b = 0.04f + 0.02f * r;
  }
  for (int r = 0; r + 1 < rows; ++r) {
    table[r].a_step = table[r + 1].a - table[r].a;
    table[r].b_step = table[r + 1].b - table[r].b;
  }
  return table;
}

// A term between `row` and the next at `fraction`, of weight `weight`, at angle `theta` on the
// ellipse, its axes changed by da and db, offset c along the normal.
inline SweepTerm make_term(std::uint32_t row, float fraction, float weight, float theta, float da,
                           float db, float c) {
  SweepTerm term{};
  term.row = row;
  term.fraction = fraction;
  term.weight_below = weight * (1.0f - fraction);
  term.weight_above = weight * fraction;
  term.cos_theta = std::cos(theta);
  term.sin_theta = std::sin(theta);
  term.x_shift = da * term.cos_theta;
  term.y_shift = db * term.sin_theta;
  term.c = c;
  return term;
}

}  // namespace sweepd::deform::test
