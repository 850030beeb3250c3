// Tests for gpu::PositionMapRenderer on llvmpipe (or whatever EGL offers): values at texels
// against CPU interpolation, coverage against UV area, the gutter, camera space, validation.
#include "gpu/position_map_renderer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <memory>
#include <vector>

#include "deform/model/model.h"
#include "gpu/gpu_worker.h"
#include "tests/gpu/uv_reference.h"

namespace sweepd::gpu {
namespace {

struct UvMesh {
  std::vector<glm::vec2> uvs;
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<std::uint32_t> indices;
  PositionMapMesh view() const { return {uvs, positions, normals, indices}; }
};

struct MapImage {
  MapImage(int w, int h)
      : width(w), height(h), positions(w * h * 3), normals(w * h * 3), coverage(w * h) {}
  int width, height;
  std::vector<float> positions, normals, coverage;
  PositionMapBuffers buffers() { return {positions, normals, coverage}; }
  glm::vec3 p(int x, int y) const { return at(positions, x, y); }
  glm::vec3 n(int x, int y) const { return at(normals, x, y); }
  float a(int x, int y) const { return coverage[y * width + x]; }
  int covered() const {
    return static_cast<int>(std::count(coverage.begin(), coverage.end(), 1.f));
  }

 private:
  glm::vec3 at(const std::vector<float>& v, int x, int y) const {
    const std::size_t i = 3 * (static_cast<std::size_t>(y) * width + x);
    return {v[i], v[i + 1], v[i + 2]};
  }
};

// An affine function of uv: interpolation reproduces it exactly (up to round-off) everywhere.
glm::vec3 affine_position(glm::vec2 uv) {
  return {2.0f * uv.x - 0.3f, 0.5f + 3.0f * uv.y, 0.1f + uv.x + uv.y};
}

// A quad whose corners sit on texel centres of a 64x64 map: x 8.5..40.5, y 8.5..56.5 texels.
constexpr int kQuadMapSize = 64;
UvMesh texel_aligned_quad() {
  UvMesh quad;
  const float s = kQuadMapSize;
  quad.uvs = {
      {8.5f / s, 8.5f / s}, {40.5f / s, 8.5f / s}, {40.5f / s, 56.5f / s}, {8.5f / s, 56.5f / s}};
  for (glm::vec2 uv : quad.uvs) quad.positions.push_back(affine_position(uv));
  quad.normals.assign(4, glm::vec3(0.0f, 0.0f, 2.0f));  // not unit: the map normalises
  quad.indices = {0, 1, 2, 0, 2, 3};
  return quad;
}

// A curved n x n grid (not affine in uv) with smooth normals, inside uv [0.1, 0.9] x [0.15, 0.85].
UvMesh wavy_sheet(int n) {
  UvMesh sheet;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const float u = 0.1f + 0.8f * i / (n - 1), v = 0.15f + 0.7f * j / (n - 1);
      sheet.uvs.push_back({u, v});
      sheet.positions.push_back({u, 0.3f * std::sin(3.0f * u) * std::cos(2.0f * v), 1.5f * v});
    }
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const std::uint32_t a = j * n + i, b = a + 1, c = a + n, d = c + 1;
      sheet.indices.insert(sheet.indices.end(), {a, b, d, a, d, c});
    }
  sheet.normals = deform::compute_vertex_normals(sheet.positions, sheet.indices);
  return sheet;
}

// (GCC 12 warns on designated initialisers that leave members to their defaults.)
PositionMapOptions map_options(int width, int height, int gutter_pixels = 0,
                               std::optional<glm::mat4> view = std::nullopt) {
  PositionMapOptions options;
  options.width = width;
  options.height = height;
  options.gutter_pixels = gutter_pixels;
  options.view = view;
  return options;
}

class PositionMapRendererTest : public ::testing::Test {
 protected:
  Context context_;
  PositionMapRenderer renderer_{context_};
};

TEST_F(PositionMapRendererTest, QuadHoldsTheInterpolatedPositionsAtEveryCoveredTexel) {
  const UvMesh quad = texel_aligned_quad();
  MapImage map(kQuadMapSize, kQuadMapSize);
  renderer_.render(quad.view(), map_options(kQuadMapSize, kQuadMapSize), map.buffers());
  int covered = 0;
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) {
      const glm::vec2 centre((x + 0.5f) / map.width, (y + 0.5f) / map.height);
      if (map.a(x, y) == 1.0f) {
        ++covered;
        // Values up to 3.5 m interpolated in float32: 1e-5 is about 40 ulps.
        EXPECT_NEAR(glm::length(map.p(x, y) - affine_position(centre)), 0.0f, 1e-5f)
            << "texel " << x << "," << y;
        EXPECT_NEAR(glm::length(map.n(x, y) - glm::vec3(0, 0, 1)), 0.0f, 1e-6f);
      } else {
        ASSERT_EQ(map.a(x, y), 0.0f);
        ASSERT_EQ(map.p(x, y), glm::vec3(0.0f)) << "uncovered texel " << x << "," << y;
      }
    }
  // Corners on texel centres: the texel there is the vertex itself (float32 round-off only).
  for (std::size_t i = 0; i < quad.uvs.size(); ++i) {
    const int x = static_cast<int>(quad.uvs[i].x * kQuadMapSize);
    const int y = static_cast<int>(quad.uvs[i].y * kQuadMapSize);
    if (map.a(x, y) == 1.0f) {  // the top-left rule keeps two of the four corners
      EXPECT_NEAR(glm::length(map.p(x, y) - quad.positions[i]), 0.0f, 1e-5f);
    }
  }
  // Edges through texel centres: the top-left fill rule draws exactly 32 x 48 texels.
  EXPECT_EQ(covered, 32 * 48);
  const auto expected =
      test_reference::expected_coverage(quad.uvs, quad.indices, kQuadMapSize, kQuadMapSize);
  EXPECT_NEAR(covered, expected.texels, expected.tolerance);
}

TEST_F(PositionMapRendererTest, RowZeroHoldsVNearZero) {
  // Documented orientation: texel (x, y) has its centre at uv ((x+.5)/W, (y+.5)/H).
  const UvMesh quad = texel_aligned_quad();
  MapImage map(kQuadMapSize, kQuadMapSize);
  renderer_.render(quad.view(), map_options(kQuadMapSize, kQuadMapSize), map.buffers());
  EXPECT_EQ(map.a(20, 9), 1.0f);   // v = 9.5/64, inside 8.5..56.5
  EXPECT_EQ(map.a(20, 60), 0.0f);  // v = 60.5/64, outside
  EXPECT_EQ(map.a(45, 20), 0.0f);  // u = 45.5/64, outside 8.5..40.5
}

TEST_F(PositionMapRendererTest, CurvedSheetMatchesBarycentricInterpolationAtVertexTexels) {
  const UvMesh sheet = wavy_sheet(40);
  constexpr int kSize = 256;
  MapImage map(kSize, kSize);
  renderer_.render(sheet.view(), map_options(kSize, kSize), map.buffers());
  const auto check = test_reference::check_vertex_texels(
      sheet.uvs, sheet.positions, sheet.indices, {kSize, kSize, map.positions, map.coverage});
  std::printf("checked %d of %zu vertices, worst error / tolerance %.3f\n", check.checked,
              sheet.uvs.size(), check.worst_error_over_tolerance);
  // The sheet's UVs do not overlap: every vertex is checked.
  EXPECT_EQ(check.overlapping, 0);
  EXPECT_EQ(check.checked, static_cast<int>(sheet.uvs.size()));
  EXPECT_EQ(check.covered_mismatch, 0);
  EXPECT_EQ(check.value_mismatch, 0);
  for (const std::string& mismatch : check.mismatches) ADD_FAILURE() << mismatch;
  const auto expected = test_reference::expected_coverage(sheet.uvs, sheet.indices, kSize, kSize);
  std::printf("covered %d texels, expected %.1f +- %.1f\n", map.covered(), expected.texels,
              expected.tolerance);
  EXPECT_NEAR(map.covered(), expected.texels, expected.tolerance);
}

TEST_F(PositionMapRendererTest, CameraSpaceMapTransformsPositionsAndNormals) {
  const UvMesh quad = texel_aligned_quad();
  const glm::mat4 view = glm::lookAt(glm::vec3(1.0f, 2.0f, 5.0f), glm::vec3(0.2f, 1.0f, 0.0f),
                                     glm::vec3(0.0f, 1.0f, 0.0f));
  MapImage map(kQuadMapSize, kQuadMapSize);
  renderer_.render(quad.view(), map_options(kQuadMapSize, kQuadMapSize, 0, view), map.buffers());
  const glm::vec3 normal = glm::normalize(glm::mat3(view) * glm::vec3(0, 0, 1));
  int covered = 0;
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) {
      if (map.a(x, y) != 1.0f) continue;
      ++covered;
      const glm::vec2 centre((x + 0.5f) / map.width, (y + 0.5f) / map.height);
      const glm::vec3 expected = glm::vec3(view * glm::vec4(affine_position(centre), 1.0f));
      // Camera distances up to ~6 m: 2e-5 covers float32 round-off of interpolation and matrix.
      EXPECT_NEAR(glm::length(map.p(x, y) - expected), 0.0f, 2e-5f);
      EXPECT_NEAR(glm::length(map.n(x, y) - normal), 0.0f, 1e-6f);
    }
  EXPECT_EQ(covered, 32 * 48);
}

TEST_F(PositionMapRendererTest, GutterCopiesTheNearestCoveredTexelAndKeepsCoverageZero) {
  const UvMesh quad = texel_aligned_quad();  // covers x 8..39, y 8..55
  MapImage plain(kQuadMapSize, kQuadMapSize), dilated(kQuadMapSize, kQuadMapSize);
  renderer_.render(quad.view(), map_options(kQuadMapSize, kQuadMapSize), plain.buffers());
  renderer_.render(quad.view(), map_options(kQuadMapSize, kQuadMapSize, 2), dilated.buffers());
  EXPECT_EQ(dilated.coverage, plain.coverage);  // A marks real coverage only
  for (int y = 8; y <= 55; ++y) {
    // Left border: 1 and 2 texels out copy the border texel bit for bit; 3 out stays empty.
    EXPECT_EQ(dilated.p(7, y), plain.p(8, y));
    EXPECT_EQ(dilated.p(6, y), plain.p(8, y));
    EXPECT_EQ(dilated.n(6, y), plain.n(8, y));
    EXPECT_EQ(dilated.p(5, y), glm::vec3(0.0f));
    // Right border (last covered column 39).
    EXPECT_EQ(dilated.p(41, y), plain.p(39, y));
    EXPECT_EQ(dilated.p(42, y), glm::vec3(0.0f));
  }
  // Corner: the diagonal neighbour fills (7, 7) in the first pass.
  EXPECT_EQ(dilated.p(7, 7), plain.p(8, 8));
  // Covered texels are untouched.
  for (int y = 8; y <= 55; ++y)
    for (int x = 8; x <= 39; ++x) ASSERT_EQ(dilated.p(x, y), plain.p(x, y));
}

TEST_F(PositionMapRendererTest, RejectsInputsThatDoNotFitTogether) {
  UvMesh quad = texel_aligned_quad();
  MapImage map(16, 16);
  quad.uvs.pop_back();
  EXPECT_NE(renderer_.validate(quad.view(), map_options(16, 16), map.buffers()).find("UVs"),
            std::string::npos);
  EXPECT_THROW(renderer_.render(quad.view(), map_options(16, 16), map.buffers()),
               std::invalid_argument);
  quad = texel_aligned_quad();
  quad.indices.push_back(99);
  quad.indices.push_back(0);
  quad.indices.push_back(1);
  EXPECT_NE(
      renderer_.validate(quad.view(), map_options(16, 16), map.buffers()).find("out of range"),
      std::string::npos);
  quad = texel_aligned_quad();
  EXPECT_NE(
      renderer_.validate(quad.view(), map_options(32, 16), map.buffers()).find("positions buffer"),
      std::string::npos);
  EXPECT_NE(renderer_.validate(quad.view(), map_options(0, 16), map.buffers()).find("size"),
            std::string::npos);
  EXPECT_EQ(renderer_.validate(quad.view(), map_options(16, 16), map.buffers()), "");
}

TEST(PositionMapOnWorker, RendersThroughTheGpuWorkerThread) {
  Worker worker;
  const UvMesh quad = texel_aligned_quad();
  MapImage map(kQuadMapSize, kQuadMapSize);
  worker
      .submit([&](Context& context) {
        PositionMapRenderer renderer(context);
        renderer.render(quad.view(), map_options(kQuadMapSize, kQuadMapSize), map.buffers());
      })
      .get();
  EXPECT_EQ(map.covered(), 32 * 48);
  EXPECT_NEAR(glm::length(map.p(20, 30) - affine_position({20.5f / 64, 30.5f / 64})), 0.0f,
              1e-5f);  // float32 round-off, as above
}

}  // namespace
}  // namespace sweepd::gpu
