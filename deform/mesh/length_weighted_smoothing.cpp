#include "deform/mesh/length_weighted_smoothing.h"

#include <array>
#include <bit>
#include <numeric>

#include "deform/mesh/disjoint_sets.h"
#include "deform/simd/vertex_blocks.h"

namespace sweepd::deform {

namespace {

// Whether a float is +0 to the bit: a column that is +0 in every row a pass reads stays +0
// (0.5·0 + Σ w·0 adds +0 to +0), so a region of the mesh where it is need not pass over it.
bool positive_zero(float value) { return std::bit_cast<std::uint32_t>(value) == 0u; }

}  // namespace

// `passes` passes over a packed group: rows first.size() - 1 of `current` (Width columns, or
// `width` where Width is 0) from themselves and their neighbours; the result in `current`.
template <std::size_t Width>
void LengthWeightedSmoothing::packed_passes(std::span<const std::uint32_t> first,
                                            std::span<const Neighbour> neighbours, int passes,
                                            std::vector<float>& current, std::vector<float>& next,
                                            std::size_t width) {
  if constexpr (Width > 0) width = Width;
  const std::size_t rows = first.size() - 1;
  for (int pass = 0; pass < passes; ++pass) {
    for (std::size_t i = 0; i < rows; ++i) {
      float* out = &next[i * width];
      for (std::size_t c = 0; c < width; ++c) out[c] = 0.5f * current[i * width + c];
      for (std::uint32_t n = first[i]; n < first[i + 1]; ++n) {
        const float* in = &current[neighbours[n].row * width];
        const float weight = neighbours[n].weight;
        for (std::size_t c = 0; c < width; ++c) out[c] += weight * in[c];
      }
    }
    current.swap(next);
  }
}

// The passes run one connected group of chosen rows at a time (rows joined when one is the
// other's neighbour: what one pass spreads stays inside its group and the border rows around
// it), on a packed copy of the group's rows and border rows that holds only the columns not +0
// everywhere in them: a share or joint weight lives near where it is painted, so a group reads
// two or three of the table's columns. Each value is computed by the same products and sums in
// the same order as a pass over the whole table, so the result is the same to the bit. A group
// writes its own rows alone and reads no other group's (a row beside a chosen row is in its
// group or a border row, which no group writes), so groups run on `threads` threads at once,
// each thread a share of the groups by their neighbour count, largest first.
void LengthWeightedSmoothing::smooth(int columns, int passes, std::vector<float>& table,
                                     int threads) const {
  if (passes <= 0 || rows_.empty() || columns <= 0) return;
  const std::size_t table_rows = table.size() / static_cast<std::size_t>(columns);
  constexpr std::uint32_t kNotChosen = ~0u;
  std::vector<std::uint32_t> chosen_at(table_rows, kNotChosen);
  for (std::size_t i = 0; i < rows_.size(); ++i)
    chosen_at[rows_[i]] = static_cast<std::uint32_t>(i);
  DisjointSets joined(rows_.size());
  for (std::size_t i = 0; i < rows_.size(); ++i)
    for (std::uint32_t n = first_[i]; n < first_[i + 1]; ++n)
      if (const std::uint32_t j = chosen_at[neighbours_[n].row]; j != kNotChosen)
        joined.join(static_cast<std::uint32_t>(i), j);
  std::vector<std::vector<std::uint32_t>> groups(rows_.size());
  for (std::size_t i = 0; i < rows_.size(); ++i)
    groups[joined.find(static_cast<std::uint32_t>(i))].push_back(static_cast<std::uint32_t>(i));
  std::erase_if(groups, [](const std::vector<std::uint32_t>& group) { return group.empty(); });

  // Each thread's groups: the largest (by neighbours, what a pass reads) to the least loaded.
  const std::size_t lanes =
      std::clamp<std::size_t>(threads < 1 ? 1 : static_cast<std::size_t>(threads), 1,
                              std::max<std::size_t>(groups.size(), 1));
  std::vector<std::size_t> work(groups.size(), 0), by_work(groups.size());
  for (std::size_t g = 0; g < groups.size(); ++g)
    for (const std::uint32_t i : groups[g]) work[g] += first_[i + 1] - first_[i];
  std::iota(by_work.begin(), by_work.end(), std::size_t{0});
  std::stable_sort(by_work.begin(), by_work.end(),
                   [&](std::size_t a, std::size_t b) { return work[a] > work[b]; });
  std::vector<std::vector<std::size_t>> lane_groups(lanes);
  std::vector<std::size_t> lane_work(lanes, 0);
  for (const std::size_t g : by_work) {
    const auto lane = static_cast<std::size_t>(
        std::min_element(lane_work.begin(), lane_work.end()) - lane_work.begin());
    lane_groups[lane].push_back(g);
    lane_work[lane] += work[g];
  }
  run_in_vertex_blocks(lanes, static_cast<int>(lanes), [&](std::size_t begin, std::size_t end) {
    for (std::size_t lane = begin; lane < end; ++lane)
      smooth_groups(groups, lane_groups[lane], columns, passes, table);
  });
}

void LengthWeightedSmoothing::smooth_groups(const std::vector<std::vector<std::uint32_t>>& groups,
                                            std::span<const std::size_t> chosen, int columns,
                                            int passes, std::vector<float>& table) const {
  const std::size_t table_rows = table.size() / static_cast<std::size_t>(columns);
  constexpr std::uint32_t kUnplaced = ~0u;
  std::vector<std::uint32_t> local(table_rows, kUnplaced);  // a table row's place in the group
  std::vector<std::uint32_t> local_rows, first;
  std::vector<Neighbour> packed_neighbours;
  std::vector<int> active;
  std::vector<float> current, next;
  for (const std::size_t g : chosen) {
    const std::vector<std::uint32_t>& group = groups[g];
    // The group's rows first (in the order they were added), then its border rows.
    local_rows.clear();
    for (const std::uint32_t i : group) {
      local[rows_[i]] = static_cast<std::uint32_t>(local_rows.size());
      local_rows.push_back(rows_[i]);
    }
    packed_neighbours.clear();
    first.assign(1, 0u);
    for (const std::uint32_t i : group) {
      for (std::uint32_t n = first_[i]; n < first_[i + 1]; ++n) {
        const std::uint32_t row = neighbours_[n].row;
        if (local[row] == kUnplaced) {
          local[row] = static_cast<std::uint32_t>(local_rows.size());
          local_rows.push_back(row);
        }
        packed_neighbours.push_back({local[row], neighbours_[n].weight});
      }
      first.push_back(static_cast<std::uint32_t>(packed_neighbours.size()));
    }
    active.clear();
    for (int c = 0; c < columns; ++c)
      for (const std::uint32_t row : local_rows)
        if (!positive_zero(table[row * columns + c])) {
          active.push_back(c);
          break;
        }
    const std::size_t width = active.size();
    if (width > 0) {
      current.resize(local_rows.size() * width);
      for (std::size_t r = 0; r < local_rows.size(); ++r)
        for (std::size_t c = 0; c < width; ++c)
          current[r * width + c] = table[local_rows[r] * columns + active[c]];
      next = current;  // the border rows, which no pass writes
      // A group reads two or three columns: loops of a known width up to 4, else of any.
      constexpr std::array kPasses{&packed_passes<0>, &packed_passes<1>, &packed_passes<2>,
                                   &packed_passes<3>, &packed_passes<4>};
      kPasses[width < kPasses.size() ? width : 0](first, packed_neighbours, passes, current, next,
                                                  width);
      for (std::size_t i = 0; i < group.size(); ++i)
        for (std::size_t c = 0; c < width; ++c)
          table[local_rows[i] * columns + active[c]] = current[i * width + c];
    }
    for (const std::uint32_t row : local_rows) local[row] = kUnplaced;
  }
}

}  // namespace sweepd::deform
