#include "gpu/texel_gutter.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace sweepd::gpu {
namespace {

constexpr int kNeighbours[8][2] = {{-1, 0},  {1, 0},  {0, -1}, {0, 1},
                                   {-1, -1}, {1, -1}, {-1, 1}, {1, 1}};

}  // namespace

void fill_texel_gutter(int width, int height, std::span<const float> coverage, int passes,
                       std::span<float> positions, std::span<float> normals) {
  if (passes <= 0) return;
  const std::size_t texels = static_cast<std::size_t>(width) * height;
  std::vector<std::uint8_t> filled(texels);
  for (std::size_t t = 0; t < texels; ++t) filled[t] = coverage[t] > 0.5f;
  // Round r's candidates: the unfilled neighbours of the texels filled in round r - 1 (for
  // round 1, of every covered texel). `queued` keeps each candidate once per round.
  std::vector<std::uint32_t> sources, candidates, filled_now;
  std::vector<int> queued(texels, -1);
  for (std::size_t t = 0; t < texels; ++t)
    if (filled[t]) filled_now.push_back(static_cast<std::uint32_t>(t));
  for (int round = 0; round < passes && !filled_now.empty(); ++round) {
    candidates.clear();
    for (const std::uint32_t t : filled_now) {
      const int x = static_cast<int>(t % width), y = static_cast<int>(t / width);
      for (const auto& [dx, dy] : kNeighbours) {
        const int nx = x + dx, ny = y + dy;
        if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
        const std::uint32_t n = static_cast<std::uint32_t>(ny * width + nx);
        if (filled[n] || queued[n] == round) continue;
        queued[n] = round;
        candidates.push_back(n);
      }
    }
    // Each candidate's source is chosen from the texels filled before this round, in the
    // rule's order; the copies go in after all sources are chosen.
    sources.resize(candidates.size());
    for (std::size_t c = 0; c < candidates.size(); ++c) {
      const int x = static_cast<int>(candidates[c] % width);
      const int y = static_cast<int>(candidates[c] / width);
      for (const auto& [dx, dy] : kNeighbours) {
        const int nx = x + dx, ny = y + dy;
        if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
        const std::uint32_t n = static_cast<std::uint32_t>(ny * width + nx);
        if (filled[n]) {
          sources[c] = n;
          break;
        }
      }
    }
    for (std::size_t c = 0; c < candidates.size(); ++c) {
      const std::uint32_t to = candidates[c], from = sources[c];
      std::copy_n(positions.begin() + 3 * from, 3, positions.begin() + 3 * to);
      if (!normals.empty()) std::copy_n(normals.begin() + 3 * from, 3, normals.begin() + 3 * to);
      filled[to] = 1;
    }
    filled_now.swap(candidates);
  }
}

}  // namespace sweepd::gpu
