// length_weighted_smoothing: smooths chosen rows of a dense per-vertex table over a mesh at bind
// time. Each pass replaces every chosen row by half itself plus half the mean of its mesh
// neighbours' rows, each neighbour weighted by 1 / edge length, so a jump spreads over a
// distance rather than over a count of edges (which matters where the mesh is dense); the other
// rows stay as they are and hold the border. Used for the sweeps' shares where sweeps meet
// (sweep_blending) and for the skinned share's weights around the shoulders
// (skinned_share_influences).
#pragma once

#include <algorithm>
#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

namespace sweepd::deform {

class LengthWeightedSmoothing {
 public:
  // Chooses `row`, at position `at`, with its mesh neighbours (each once, at least one):
  // row_of(u) is a neighbour's row in the table, position_of(u) its position.
  template <class RowOf, class PositionOf>
  void add(std::uint32_t row, glm::vec3 at, std::span<const std::uint32_t> neighbours, RowOf row_of,
           PositionOf position_of) {
    auto inverse_length = [&](std::uint32_t u) {
      return 1.0f / std::max(glm::length(position_of(u) - at), 1e-6f);
    };
    float total = 0.0f;
    for (std::uint32_t u : neighbours) total += inverse_length(u);
    for (std::uint32_t u : neighbours)
      neighbours_.push_back({row_of(u), 0.5f * inverse_length(u) / total});
    rows_.push_back(row);
    first_.push_back(static_cast<std::uint32_t>(neighbours_.size()));
  }

  // `passes` passes over `table` (rows of `columns` values).
  void smooth(int columns, int passes, std::vector<float>& table) const;

 private:
  struct Neighbour {
    std::uint32_t row;
    float weight;  // half in all per chosen row: the row keeps the other half
  };
  std::vector<std::uint32_t> rows_, first_{0};
  std::vector<Neighbour> neighbours_;
};

}  // namespace sweepd::deform
