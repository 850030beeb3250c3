// LengthWeightedSmoothing::smooth against the plain pass it replaces (every chosen row, every
// column of the whole table, each pass): the group-by-group, packed-column passes, on one
// thread or several, must give the same table to the bit, because the binding's shares and the self-check's verdicts are
// compared to the bit across changes (the corpus gate's ledger).
#include "deform/mesh/length_weighted_smoothing.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

namespace sweepd::deform {
namespace {

// A grid of `side` x `side` vertices, each joined to its 4-neighbours (edge lengths varying).
struct SmoothingGrid {
  int side = 0;
  std::vector<std::vector<std::uint32_t>> neighbours;
  std::vector<std::vector<float>> lengths;
};

SmoothingGrid smoothing_grid(int side, std::mt19937& random) {
  SmoothingGrid g;
  g.side = side;
  g.neighbours.resize(side * side);
  g.lengths.resize(side * side);
  std::uniform_real_distribution<float> length(0.002f, 0.03f);
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      const int v = y * side + x;
      for (const auto& [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
        const int nx = x + dx, ny = y + dy;
        if (nx < 0 || ny < 0 || nx >= side || ny >= side) continue;
        g.neighbours[v].push_back(static_cast<std::uint32_t>(ny * side + nx));
        g.lengths[v].push_back(length(random));
      }
    }
  return g;
}

// The pass smooth() is defined by: half each chosen row plus its weighted neighbours, over the
// whole table.
void plain_passes(const std::vector<std::uint32_t>& rows,
                  const std::vector<std::vector<std::pair<std::uint32_t, float>>>& weighted,
                  int columns, int passes, std::vector<float>& table) {
  std::vector<float> next = table;
  for (int pass = 0; pass < passes; ++pass) {
    for (std::size_t i = 0; i < rows.size(); ++i) {
      float* out = &next[rows[i] * columns];
      for (int c = 0; c < columns; ++c) out[c] = 0.5f * table[rows[i] * columns + c];
      for (const auto& [row, weight] : weighted[i])
        for (int c = 0; c < columns; ++c) out[c] += weight * table[row * columns + c];
    }
    table.swap(next);
  }
}

TEST(LengthWeightedSmoothing, PassesGroupByGroupOnTheirOwnColumnsGiveTheWholeTablesPassesToTheBit) {
  std::mt19937 random(47);
  const SmoothingGrid g = smoothing_grid(40, random);
  constexpr int kColumns = 7;
  // Five separate groups of chosen rows (rectangles of the grid), each where other columns are
  // painted, so that they read 1, 2, 3 and 5 columns (the packed loops of known widths and the
  // general one); one column is painted nowhere.
  std::vector<float> table(g.side * g.side * kColumns, 0.0f);
  std::uniform_real_distribution<float> share(0.0f, 1.0f);
  for (int y = 0; y < g.side; ++y)
    for (int x = 0; x < g.side; ++x) {
      float* row = &table[(y * g.side + x) * kColumns];
      if ((y < 20 && x < 25) || (x >= 12 && x < 18 && y >= 26)) row[6] = 0.25f;
      if (x < 15) row[0] = share(random);
      if (x >= 12 && x < 20) row[1] = share(random);
      if (y >= 30) row[2] = share(random);
      if (x >= 30 && y < 10) row[3 + (x + y) % 2] = share(random);
      if (x >= 35 && y >= 18 && y < 28) row[3] = share(random);
      if (x >= 13 && x < 17 && y >= 29) row[5] = share(random);
    }
  const auto inside = [](int x, int y, int x0, int x1, int y0, int y1) {
    return x >= x0 && x < x1 && y >= y0 && y < y1;
  };
  std::vector<std::uint32_t> rows;
  for (int y = 0; y < g.side; ++y)
    for (int x = 0; x < g.side; ++x)
      if (inside(x, y, 10, 18, 5, 24) || inside(x, y, 2, 9, 31, 38) || inside(x, y, 28, 36, 2, 8) ||
          inside(x, y, 13, 17, 29, 36) || inside(x, y, 36, 39, 20, 26))
        rows.push_back(static_cast<std::uint32_t>(y * g.side + x));
  LengthWeightedSmoothing smoothing;
  std::vector<std::vector<std::pair<std::uint32_t, float>>> weighted;
  for (const std::uint32_t v : rows) {
    smoothing.add(v, g.neighbours[v], g.lengths[v], [](std::uint32_t u) { return u; });
    // The weights add() gives: half in all, by inverse length.
    float total = 0.0f;
    for (const float length : g.lengths[v]) total += 1.0f / length;
    weighted.emplace_back();
    for (std::size_t i = 0; i < g.neighbours[v].size(); ++i)
      weighted.back().push_back({g.neighbours[v][i], 0.5f * (1.0f / g.lengths[v][i]) / total});
  }
  const std::vector<float> painted = table;
  std::vector<float> expected = table;
  plain_passes(rows, weighted, kColumns, 37, expected);
  smoothing.smooth(kColumns, 37, table);
  ASSERT_EQ(table.size(), expected.size());
  EXPECT_EQ(std::memcmp(table.data(), expected.data(), table.size() * sizeof(float)), 0);
  // The passes moved the chosen rows (two unchanged tables would prove nothing): the first
  // group's column 0 borders zeros at x = 15, so its row at x = 14 changes by more than 1e-3.
  const std::size_t at = (10 * g.side + 14) * kColumns + 0;
  EXPECT_GT(std::abs(table[at] - painted[at]), 1e-3f);
  // The groups on several threads at once (bind smooths on two): the same table to the bit.
  for (const int threads : {2, 3, 8}) {
    SCOPED_TRACE(threads);
    std::vector<float> threaded = painted;
    smoothing.smooth(kColumns, 37, threaded, threads);
    EXPECT_EQ(std::memcmp(threaded.data(), expected.data(), threaded.size() * sizeof(float)), 0);
  }
}

}  // namespace
}  // namespace sweepd::deform
