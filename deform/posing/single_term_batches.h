// SingleTermBatches: sweep terms eight at a time, each written to its own output point — the
// sweep fast path for the commonest vertex, one moved by a single sweep term and no skinned share
// (43 % of the 72k mannequin's vertices; the output is its position), and for every other
// vertex's terms (the output is a term point that the vertex's loop adds; sweep_vertex_kinds.h).
// Below, "vertex" is the output's index.
//
// The vertices are sorted by their term's table row and packed into batches of kLanes that read
// the same two rows, so a batch's row data are the same in every lane (broadcast) and its
// per-vertex data (fraction, cos θ, sin θ, shifts, c, g0, g1) are stored lane by lane (structure
// of arrays): one lane per vertex, x, y and z computed apart, no gathers and no horizontal sums.
// A row's last batch is padded with copies of its last vertex (the same vertex written with the
// same value, from the same batch).
// The formula is the sweep term of sweep_vertex_kinds.h, in the same order of operations:
//   a(f) = a + f a_step, x = a(f) cos θ + da cos θ (y likewise with b, sin θ),
//   at(r) = ((C_r + x X_r) + y Y_r) + c N_r,  p = at(row) g0 + at(row + 1) g1.
// Items are kLanes per batch; evaluate() takes ranges that start at a batch boundary (a multiple
// of kLanes; run_in_vertex_blocks' granule) and computes each vertex by the same code whatever
// the range, so results do not depend on how the items are split between threads.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "deform/posing/sweep_vertex_kinds.h"

namespace sweepd::deform {

class SingleTermBatches {
 public:
  static constexpr std::size_t kLanes = 8;

  // Item i writes output vertices[i] with terms[i] alone.
  SingleTermBatches(std::span<const std::uint32_t> vertices, std::span<const SweepTerm> terms,
                    VertexLoopInstructions instructions);

  std::size_t item_count() const { return row_.size() * kLanes; }

  // Writes the outputs of the items [begin, end); begin is a multiple of kLanes, end of kLanes or
  // item_count().
  void evaluate(std::span<const SweepSample> table, std::span<glm::vec3> outputs, std::size_t begin,
                std::size_t end) const;

  // The same points lane by lane: batch i's x, y and z lanes (kLanes floats each) to
  // lanes[3 kLanes i, 3 kLanes (i + 1)); lanes holds 3 × item_count() floats.
  void evaluate_lane_by_lane(std::span<const SweepSample> table, std::span<float> lanes,
                             std::size_t begin, std::size_t end) const;
  // Per output index in [0, outputs): where evaluate_lane_by_lane writes its x (y follows kLanes
  // floats later, z 2 kLanes).
  std::vector<std::uint32_t> lane_offsets(std::size_t outputs) const;

  struct Batch {  // kLanes vertices on the same two rows, lane by lane
    std::array<float, kLanes> fraction, cos_theta, sin_theta, x_shift, y_shift, c, weight_below,
        weight_above;
    std::array<std::uint32_t, kLanes> vertex;
  };

 private:
  VertexLoopInstructions instructions_;
  std::vector<std::uint32_t> row_;  // per batch
  std::vector<Batch> batches_;
};

}  // namespace sweepd::deform
