// TexelGutter against the rule it documents, written the plainest way (every round a full
// pass over the map, sources from a copy of the previous round): bit-for-bit equal on the
// mannequin's real UV atlas (islands, seams, thin strips, the map's edges) and on random
// coverage, and on the renderer's own output.
#include "gpu/texel_gutter.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "gpu/egl_context.h"
#include "gpu/position_map_renderer.h"
#include "mannequin/mannequin.h"

namespace sweepd::gpu {
namespace {

struct Map {
  std::vector<float> p, n, a;
};

// The rule, literally: rounds of full passes reading the previous round's map.
Map reference_gutter(int width, int height, Map map, int passes) {
  const int neighbours[8][2] = {{-1, 0},  {1, 0},  {0, -1}, {0, 1},
                                {-1, -1}, {1, -1}, {-1, 1}, {1, 1}};
  std::vector<bool> filled(map.a.size());
  for (std::size_t t = 0; t < filled.size(); ++t) filled[t] = map.a[t] > 0.5f;
  for (int round = 0; round < passes; ++round) {
    const Map before = map;
    const std::vector<bool> filled_before = filled;
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const int t = y * width + x;
        if (filled_before[t]) continue;
        for (const auto& [dx, dy] : neighbours) {
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
          const int s = ny * width + nx;
          if (!filled_before[s]) continue;
          for (int c = 0; c < 3; ++c) {
            map.p[3 * t + c] = before.p[3 * s + c];
            map.n[3 * t + c] = before.n[3 * s + c];
          }
          filled[t] = true;
          break;
        }
      }
    }
  }
  return map;
}

TEST(TexelGutter, EqualsTheRuleOnTheMannequinsAtlas) {
  const deform::Model model = mannequin::make_mannequin({.target_vertices = 20000});
  Context context;
  PositionMapRenderer renderer(context);
  constexpr int kWidth = 256, kHeight = 192;  // not square: rows and columns not swapped
  Map plain{std::vector<float>(kWidth * kHeight * 3), std::vector<float>(kWidth * kHeight * 3),
            std::vector<float>(kWidth * kHeight)};
  renderer.render({model.uvs, model.positions, model.normals, model.indices},
                  {.width = kWidth, .height = kHeight, .gutter_pixels = 0, .view = std::nullopt},
                  {plain.p, plain.n, plain.a});
  TexelGutter gutter;  // one for every round count: its kept scratch must not leak between calls
  for (const int passes : {1, 4, 9}) {
    SCOPED_TRACE(std::to_string(passes) + " passes");
    const Map expected = reference_gutter(kWidth, kHeight, plain, passes);
    Map filled = plain;
    gutter.fill(kWidth, kHeight, filled.a, passes, filled.p, filled.n);
    EXPECT_EQ(filled.p, expected.p);
    EXPECT_EQ(filled.n, expected.n);
    // The renderer's own gutter is this one.
    Map rendered = plain;
    renderer.render(
        {model.uvs, model.positions, model.normals, model.indices},
        {.width = kWidth, .height = kHeight, .gutter_pixels = passes, .view = std::nullopt},
        {rendered.p, rendered.n, rendered.a});
    EXPECT_EQ(rendered.p, expected.p);
    EXPECT_EQ(rendered.n, expected.n);
    EXPECT_EQ(rendered.a, plain.a) << "coverage marks real coverage only";
    // The check can fail: the gutter changed texels.
    EXPECT_NE(expected.p, plain.p);
  }
}

TEST(TexelGutter, EqualsTheRuleOnRandomCoverageAndWithoutNormals) {
  constexpr int kWidth = 61, kHeight = 47;
  std::mt19937 random(5);
  Map map{std::vector<float>(kWidth * kHeight * 3), std::vector<float>(kWidth * kHeight * 3),
          std::vector<float>(kWidth * kHeight)};
  for (std::size_t t = 0; t < map.a.size(); ++t) {
    map.a[t] = random() % 7 == 0 ? 1.0f : 0.0f;  // sparse specks: many competing sources
    for (int c = 0; c < 3 && map.a[t] > 0.5f; ++c) {
      map.p[3 * t + c] = static_cast<float>(random() % 1000);
      map.n[3 * t + c] = static_cast<float>(random() % 1000);
    }
  }
  const Map expected = reference_gutter(kWidth, kHeight, map, 3);
  Map filled = map;
  TexelGutter gutter;
  gutter.fill(kWidth, kHeight, filled.a, 3, filled.p, filled.n);
  EXPECT_EQ(filled.p, expected.p);
  EXPECT_EQ(filled.n, expected.n);
  Map positions_only = map;
  gutter.fill(kWidth, kHeight, positions_only.a, 3, positions_only.p, {});
  EXPECT_EQ(positions_only.p, expected.p);
  EXPECT_EQ(positions_only.n, map.n) << "no normals given: none touched";
}

}  // namespace
}  // namespace sweepd::gpu
