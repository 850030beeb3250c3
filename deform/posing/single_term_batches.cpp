#include "deform/posing/single_term_batches.h"

#include <algorithm>
#include <cstring>
#include <numeric>

#include "deform/simd/float_lanes.h"

namespace sweepd::deform {

namespace {

using Batch = SingleTermBatches::Batch;

// By reference: a vector returned by value would change the ABI with the target (-Wpsabi).
[[gnu::always_inline]] inline void load(
    FloatLanes8& lanes, const std::array<float, SingleTermBatches::kLanes>& values) {
  std::memcpy(&lanes, values.data(), sizeof(lanes));
}

// Where a batch's points go: to outputs[vertex[lane]] (kScattered), or lane by lane to
// lanes[3 kLanes i, 3 kLanes (i + 1)) for batch i (kLaneByLane: x, y, z lanes, three stores).
enum class Output { kScattered, kLaneByLane };

// Batches [0, count): kLanes vertices each, every lane computed alike. Inlined into one function
// per instruction set and output (on AVX2 the sums contract into fused multiply-adds).
template <Output kOutput>
[[gnu::always_inline]] inline void evaluate_batches(const Batch* batches, const std::uint32_t* rows,
                                                    std::size_t count, const SweepSample* table,
                                                    glm::vec3* outputs, float* lanes) {
  for (std::size_t i = 0; i < count; ++i) {
    const Batch& batch = batches[i];
    const SweepSample& below = table[rows[i]];
    const SweepSample& above = table[rows[i] + 1];
    FloatLanes8 f, cos_theta, sin_theta, x_shift, y_shift, c, weight_below, weight_above;
    load(f, batch.fraction);
    load(cos_theta, batch.cos_theta);
    load(sin_theta, batch.sin_theta);
    load(x_shift, batch.x_shift);
    load(y_shift, batch.y_shift);
    load(c, batch.c);
    load(weight_below, batch.weight_below);
    load(weight_above, batch.weight_above);
    const FloatLanes8 x = (below.a + f * below.a_step) * cos_theta + x_shift;
    const FloatLanes8 y = (below.b + f * below.b_step) * sin_theta + y_shift;
    FloatLanes8 p[3];
    for (int axis = 0; axis < 3; ++axis) {
      const FloatLanes8 at_below = below.centre[axis] + x * below.x_axis[axis] +
                                   y * below.y_axis[axis] + c * below.normal[axis];
      const FloatLanes8 at_above = above.centre[axis] + x * above.x_axis[axis] +
                                   y * above.y_axis[axis] + c * above.normal[axis];
      p[axis] = at_below * weight_below + at_above * weight_above;
    }
    if constexpr (kOutput == Output::kLaneByLane) {
      std::memcpy(lanes + 3 * SingleTermBatches::kLanes * i, p, sizeof(p));
    } else {
      for (std::size_t lane = 0; lane < SingleTermBatches::kLanes; ++lane)
        outputs[batch.vertex[lane]] = glm::vec3(p[0][lane], p[1][lane], p[2][lane]);
    }
  }
}

template <Output kOutput>
void evaluate_batches_baseline(const Batch* batches, const std::uint32_t* rows, std::size_t count,
                               const SweepSample* table, glm::vec3* outputs, float* lanes) {
  evaluate_batches<kOutput>(batches, rows, count, table, outputs, lanes);
}

#if defined(__x86_64__)
template <Output kOutput>
[[gnu::target("avx2,fma")]] void evaluate_batches_avx2(const Batch* batches,
                                                       const std::uint32_t* rows, std::size_t count,
                                                       const SweepSample* table, glm::vec3* outputs,
                                                       float* lanes) {
  evaluate_batches<kOutput>(batches, rows, count, table, outputs, lanes);
}
#endif

template <Output kOutput>
void evaluate_range(VertexLoopInstructions instructions, const Batch* batches,
                    const std::uint32_t* rows, std::size_t count, const SweepSample* table,
                    glm::vec3* outputs, float* lanes) {
#if defined(__x86_64__)
  if (instructions == VertexLoopInstructions::kAvx2Fma) {
    evaluate_batches_avx2<kOutput>(batches, rows, count, table, outputs, lanes);
    return;
  }
#endif
  (void)instructions;
  evaluate_batches_baseline<kOutput>(batches, rows, count, table, outputs, lanes);
}

}  // namespace

SingleTermBatches::SingleTermBatches(std::span<const std::uint32_t> vertices,
                                     std::span<const SweepTerm> terms,
                                     VertexLoopInstructions instructions)
    : instructions_(instructions) {
  // By row, then by vertex (so neighbours on a ring stay together).
  std::vector<std::size_t> order(vertices.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) {
    return terms[i].row != terms[j].row ? terms[i].row < terms[j].row : vertices[i] < vertices[j];
  });
  // A batch's unused lanes repeat its last vertex.
  const auto fill_last_batch = [&](std::size_t lane) {
    Batch& last = batches_.back();
    for (; lane < kLanes; ++lane) {
      last.fraction[lane] = last.fraction[lane - 1];
      last.cos_theta[lane] = last.cos_theta[lane - 1];
      last.sin_theta[lane] = last.sin_theta[lane - 1];
      last.x_shift[lane] = last.x_shift[lane - 1];
      last.y_shift[lane] = last.y_shift[lane - 1];
      last.c[lane] = last.c[lane - 1];
      last.weight_below[lane] = last.weight_below[lane - 1];
      last.weight_above[lane] = last.weight_above[lane - 1];
      last.vertex[lane] = last.vertex[lane - 1];
    }
  };
  std::size_t lane = kLanes;
  for (const std::size_t i : order) {
    const SweepTerm& term = terms[i];
    if (lane == kLanes || row_.back() != term.row) {
      if (!batches_.empty()) fill_last_batch(lane);
      batches_.emplace_back();
      row_.push_back(term.row);
      lane = 0;
    }
    Batch& batch = batches_.back();
    batch.fraction[lane] = term.fraction;
    batch.cos_theta[lane] = term.cos_theta;
    batch.sin_theta[lane] = term.sin_theta;
    batch.x_shift[lane] = term.x_shift;
    batch.y_shift[lane] = term.y_shift;
    batch.c[lane] = term.c;
    batch.weight_below[lane] = term.weight_below;
    batch.weight_above[lane] = term.weight_above;
    batch.vertex[lane] = vertices[i];
    ++lane;
  }
  if (!batches_.empty()) fill_last_batch(lane);
}

void SingleTermBatches::evaluate(std::span<const SweepSample> table, std::span<glm::vec3> outputs,
                                 std::size_t begin, std::size_t end) const {
  const std::size_t first = begin / kLanes, last = (end + kLanes - 1) / kLanes;
  if (first >= last) return;
  evaluate_range<Output::kScattered>(instructions_, batches_.data() + first, row_.data() + first,
                                     last - first, table.data(), outputs.data(), nullptr);
}

void SingleTermBatches::evaluate_lane_by_lane(std::span<const SweepSample> table,
                                              std::span<float> lanes, std::size_t begin,
                                              std::size_t end) const {
  const std::size_t first = begin / kLanes, last = (end + kLanes - 1) / kLanes;
  if (first >= last) return;
  evaluate_range<Output::kLaneByLane>(instructions_, batches_.data() + first, row_.data() + first,
                                      last - first, table.data(), nullptr,
                                      lanes.data() + 3 * kLanes * first);
}

std::vector<std::uint32_t> SingleTermBatches::lane_offsets(std::size_t outputs) const {
  std::vector<std::uint32_t> offset(outputs, 0);
  // Backwards, so an output padded into later lanes keeps its first lane.
  for (std::size_t i = batches_.size(); i-- > 0;)
    for (std::size_t lane = kLanes; lane-- > 0;)
      offset[batches_[i].vertex[lane]] = static_cast<std::uint32_t>(3 * kLanes * i + lane);
  return offset;
}

}  // namespace sweepd::deform
