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
#include <span>
#include <vector>

namespace sweepd::deform {

class LengthWeightedSmoothing {
 public:
  // Chooses `row` (each row once) with its mesh neighbours (each once, at least one) and the
  // lengths of the edges to them (vertex_adjacency.h): row_of(u) is a neighbour's row in the table.
  template <class RowOf>
  void add(std::uint32_t row, std::span<const std::uint32_t> neighbours,
           std::span<const float> edge_lengths, RowOf row_of) {
    auto inverse_length = [](float length) { return 1.0f / std::max(length, 1e-6f); };
    float total = 0.0f;
    for (float length : edge_lengths) total += inverse_length(length);
    for (std::size_t i = 0; i < neighbours.size(); ++i)
      neighbours_.push_back(
          {row_of(neighbours[i]), 0.5f * inverse_length(edge_lengths[i]) / total});
    rows_.push_back(row);
    first_.push_back(static_cast<std::uint32_t>(neighbours_.size()));
  }

  // `passes` passes over `table` (rows of `columns` values), on up to `threads` threads (the
  // same table to the bit for any count).
  void smooth(int columns, int passes, std::vector<float>& table, int threads = 1) const;

 private:
  struct Neighbour {
    std::uint32_t row;
    float weight;  // half in all per chosen row: the row keeps the other half
  };
  // The passes over groups[g] for each g in `chosen`.
  void smooth_groups(const std::vector<std::vector<std::uint32_t>>& groups,
                     std::span<const std::size_t> chosen, int columns, int passes,
                     std::vector<float>& table) const;
  template <std::size_t Width>
  static void packed_passes(std::span<const std::uint32_t> first,
                            std::span<const Neighbour> neighbours, int passes,
                            std::vector<float>& current, std::vector<float>& next,
                            std::size_t width = Width);
  std::vector<std::uint32_t> rows_, first_{0};
  std::vector<Neighbour> neighbours_;
};

}  // namespace sweepd::deform
