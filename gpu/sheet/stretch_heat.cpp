#include "gpu/sheet/stretch_heat.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace sweepd::sheet {

namespace {

// The colour ramp: t = 0 blue, 0.5 yellow, 1 red; t is clamped to [0, 1].
glm::vec3 heat_colour(float t) {
  const glm::vec3 blue(0.25f, 0.45f, 0.85f), yellow(0.95f, 0.85f, 0.30f), red(0.85f, 0.12f, 0.10f);
  t = std::clamp(t, 0.0f, 1.0f);
  return t < 0.5f ? glm::mix(blue, yellow, 2.0f * t) : glm::mix(yellow, red, 2.0f * t - 1.0f);
}

}  // namespace

StretchHeat::StretchHeat(std::span<const glm::vec3> rest_positions,
                         std::span<const std::uint32_t> indices) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  pairs.reserve(indices.size());
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = indices[t + k], b = indices[t + (k + 1) % 3];
      pairs.emplace_back(std::min(a, b), std::max(a, b));
    }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  for (const auto& [a, b] : pairs) {
    const float length = glm::length(rest_positions[a] - rest_positions[b]);
    if (length <= 0.0f) continue;  // a degenerate edge has no stretch to show
    edges_.push_back(a);
    edges_.push_back(b);
    rest_length_.push_back(length);
  }
}

void StretchHeat::colour(std::span<const glm::vec3> positions, float full_scale,
                         std::span<glm::vec3> colours) const {
  // colours[v].x holds the vertex's largest stretch until the ramp replaces it.
  std::fill(colours.begin(), colours.end(), glm::vec3(0.0f));
  for (std::size_t e = 0; e < rest_length_.size(); ++e) {
    const std::uint32_t a = edges_[2 * e], b = edges_[2 * e + 1];
    const float stretch =
        std::abs(glm::length(positions[a] - positions[b]) / rest_length_[e] - 1.0f);
    colours[a].x = std::max(colours[a].x, stretch);
    colours[b].x = std::max(colours[b].x, stretch);
  }
  for (glm::vec3& c : colours) c = heat_colour(c.x / full_scale);
}

}  // namespace sweepd::sheet
