#include "gpu/texel_gutter.h"

#include <algorithm>

namespace sweepd::gpu {
namespace {

constexpr int kNeighbours[8][2] = {{-1, 0},  {1, 0},  {0, -1}, {0, 1},
                                   {-1, -1}, {1, -1}, {-1, 1}, {1, 1}};

// A texel's state; kQueued is a candidate of the running round, still unfilled for its rule.
enum : std::uint8_t { kEmpty, kFilled, kQueued };

}  // namespace

void TexelGutter::fill(int width, int height, std::span<const float> coverage, int passes,
                       std::span<float> positions, std::span<float> normals) {
  if (passes <= 0) return;
  const std::size_t texels = static_cast<std::size_t>(width) * height;
  state_.resize(texels);
  border_.clear();
  for (std::size_t t = 0; t < texels; ++t) {
    state_[t] = coverage[t] > 0.5f ? kFilled : kEmpty;
    if (state_[t] == kFilled) border_.push_back(static_cast<std::uint32_t>(t));
  }
  // The neighbour of texel t at (dx, dy), or nothing off the map.
  auto neighbour = [width, height](std::uint32_t t, int dx, int dy) -> std::int64_t {
    const int x = static_cast<int>(t % width) + dx, y = static_cast<int>(t / width) + dy;
    if (x < 0 || y < 0 || x >= width || y >= height) return -1;
    return static_cast<std::int64_t>(y) * width + x;
  };
  // Round r's candidates: the empty neighbours of the texels filled in round r - 1 (for round
  // 1, of every covered texel), each once.
  for (int round = 0; round < passes && !border_.empty(); ++round) {
    candidates_.clear();
    for (const std::uint32_t t : border_) {
      for (const auto& [dx, dy] : kNeighbours) {
        const std::int64_t n = neighbour(t, dx, dy);
        if (n < 0 || state_[n] != kEmpty) continue;
        state_[n] = kQueued;
        candidates_.push_back(static_cast<std::uint32_t>(n));
      }
    }
    // Each candidate's source is chosen among the texels filled before this round, in the
    // rule's order; the copies go in after all sources are chosen.
    sources_.resize(candidates_.size());
    for (std::size_t c = 0; c < candidates_.size(); ++c) {
      for (const auto& [dx, dy] : kNeighbours) {
        const std::int64_t n = neighbour(candidates_[c], dx, dy);
        if (n >= 0 && state_[n] == kFilled) {
          sources_[c] = static_cast<std::uint32_t>(n);
          break;
        }
      }
    }
    for (std::size_t c = 0; c < candidates_.size(); ++c) {
      const std::uint32_t to = candidates_[c], from = sources_[c];
      std::copy_n(positions.begin() + 3 * from, 3, positions.begin() + 3 * to);
      if (!normals.empty()) std::copy_n(normals.begin() + 3 * from, 3, normals.begin() + 3 * to);
      state_[to] = kFilled;
    }
    border_.swap(candidates_);
  }
}

}  // namespace sweepd::gpu
