// Tests for gpu::PreviewRenderer on llvmpipe: pixels of known scenes — background in the
// corners, silhouette coverage against the analytic projected area, the shading formula at the
// centre, per-vertex colours, the default camera looking from the front, MSAA edges.
#include "gpu/preview_renderer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <numbers>
#include <vector>

#include "io/png/png_write.h"
#include "mannequin/mannequin.h"

namespace sweepd::gpu::preview_renderer_test {
namespace {

struct Mesh {
  std::vector<glm::vec3> positions, normals, colours;
  std::vector<std::uint32_t> indices;
  PreviewMesh view() const { return {positions, normals, indices, colours}; }
};

// A unit-radius UV sphere around `centre`, normals pointing out.
Mesh sphere(glm::vec3 centre, int rings = 48, int segments = 96) {
  Mesh mesh;
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s <= segments; ++s) {
      const double theta = std::numbers::pi * r / rings, phi = 2 * std::numbers::pi * s / segments;
      const glm::vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta),
                        std::sin(theta) * std::sin(phi));
      mesh.positions.push_back(centre + n);
      mesh.normals.push_back(n);
    }
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const std::uint32_t a = r * (segments + 1) + s, b = a + 1, c = a + segments + 1, d = c + 1;
      mesh.indices.insert(mesh.indices.end(), {a, c, b, b, c, d});
    }
  return mesh;
}

// The square [-h, h]^2 in the z = 0 plane, facing +Z, rotated by `angle` about Z.
Mesh square(float h, float angle = 0.0f) {
  Mesh mesh;
  const glm::mat2 rotation(std::cos(angle), std::sin(angle), -std::sin(angle), std::cos(angle));
  for (glm::vec2 corner :
       {glm::vec2(-h, -h), glm::vec2(h, -h), glm::vec2(h, h), glm::vec2(-h, h)}) {
    mesh.positions.push_back(glm::vec3(rotation * corner, 0.0f));
    mesh.normals.push_back({0.0f, 0.0f, 1.0f});
  }
  mesh.indices = {0, 1, 2, 0, 2, 3};
  return mesh;
}

// Looking down -Z from z = 5 at an orthographic window [-1, 1]^2.
Camera orthographic_front() {
  return {glm::lookAt(glm::vec3(0, 0, 5), glm::vec3(0.0f), glm::vec3(0, 1, 0)),
          glm::ortho(-1.0f, 1.0f, -1.0f, 1.0f, 0.1f, 10.0f)};
}

PreviewOptions options_for(int size, int samples, std::optional<Camera> camera = std::nullopt) {
  PreviewOptions options;
  options.width = options.height = size;
  options.samples = samples;
  options.camera = camera;
  return options;
}

struct Image {
  int width, height;
  std::vector<std::uint8_t> rgba;
  Image(int w, int h) : width(w), height(h), rgba(static_cast<std::size_t>(w) * h * 4) {}
  glm::ivec4 at(int x, int y) const {  // y = 0 is the top row
    const std::uint8_t* p = &rgba[(static_cast<std::size_t>(y) * width + x) * 4];
    return {p[0], p[1], p[2], p[3]};
  }
  int count_not(glm::ivec4 colour) const {
    int n = 0;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) n += at(x, y) != colour;
    return n;
  }
};

glm::ivec4 to_bytes(glm::vec4 colour) { return glm::ivec4(glm::round(colour * 255.0f)); }

class PreviewRendererTest : public ::testing::Test {
 protected:
  Context context_;
  PreviewRenderer renderer_{context_};
};

TEST_F(PreviewRendererTest, SquareCoversItsAreaWithTheShadedColourOnTheBackground) {
  const PreviewOptions options = options_for(64, 1, orthographic_front());
  Image image(64, 64);
  renderer_.render(square(0.5f).view(), options, image.rgba);
  const glm::ivec4 background = to_bytes(options.background);
  for (auto [x, y] : {std::pair{0, 0}, {63, 0}, {0, 63}, {63, 63}}) {
    EXPECT_EQ(image.at(x, y), background) << "corner " << x << "," << y;
  }
  // [-0.5, 0.5]^2 of the [-1, 1]^2 window: pixels 16..47 both ways, edges on pixel borders so
  // no centre is ambiguous — exactly 32 x 32.
  EXPECT_EQ(image.count_not(background), 32 * 32);
  const float lambert = std::max(glm::normalize(options.light_direction).z, 0.0f);
  const glm::vec3 shaded =
      options.base_colour * (options.ambient + (1 - options.ambient) * lambert);
  const glm::ivec4 expected = to_bytes(glm::vec4(shaded, 1.0f));
  // Float to 8-bit conversion may round either way: 1 step.
  for (int c = 0; c < 4; ++c) EXPECT_NEAR(image.at(32, 32)[c], expected[c], 1) << "channel " << c;
  // Top row first: the square's top edge (y = 0.5) is at row 16.
  EXPECT_EQ(image.at(32, 15), background);
  EXPECT_NE(image.at(32, 16), background);
}

TEST_F(PreviewRendererTest, VertexColoursReplaceTheBaseColour) {
  Mesh mesh = square(0.5f);
  mesh.colours.assign(4, glm::vec3(0.0f, 1.0f, 0.0f));
  const PreviewOptions options = options_for(32, 1, orthographic_front());
  Image image(32, 32);
  renderer_.render(mesh.view(), options, image.rgba);
  const float lambert = std::max(glm::normalize(options.light_direction).z, 0.0f);
  const int green =
      static_cast<int>(std::round(255 * (options.ambient + (1 - options.ambient) * lambert)));
  EXPECT_EQ(image.at(16, 16).x, 0);
  EXPECT_EQ(image.at(16, 16).z, 0);
  EXPECT_NEAR(image.at(16, 16).y, green, 1);  // 8-bit rounding
}

TEST_F(PreviewRendererTest, DefaultCameraFramesASphereFromTheFront) {
  // Front half (z > 0) red, back half blue: from the default camera on +Z only red shows.
  Mesh mesh = sphere({0.3f, 1.0f, -0.2f});
  for (const glm::vec3& n : mesh.normals)
    mesh.colours.push_back(n.z >= 0 ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, 1));
  constexpr int kSize = 256;
  const PreviewOptions options = options_for(kSize, 1);
  Image image(kSize, kSize);
  renderer_.render(mesh.view(), options, image.rgba);
  const glm::ivec4 background = to_bytes(options.background);
  EXPECT_EQ(image.at(0, 0), background);
  EXPECT_EQ(image.at(kSize - 1, kSize - 1), background);
  const glm::ivec4 centre = image.at(kSize / 2, kSize / 2);
  EXPECT_GT(centre.x, 100);  // lit red front
  EXPECT_EQ(centre.z, 0);
  // front_camera puts the bounding box's sphere (radius sqrt 3) tangent to a 30° view: the unit
  // sphere's disk has radius tan(asin(1/d)) / tan(15°) of the half image, d = sqrt 3 / sin 15°.
  const double d = std::sqrt(3.0) / std::sin(std::numbers::pi / 12);
  const double disk = std::tan(std::asin(1.0 / d)) / std::tan(std::numbers::pi / 12);
  const double expected_fraction = std::numbers::pi * disk * disk / 4.0;
  const double fraction = image.count_not(background) / double(kSize * kSize);
  std::printf("silhouette covers %.4f of the image, expected %.4f\n", fraction, expected_fraction);
  // Tessellation (96 segments) shrinks the disk by 0.1%; pixel sampling along the ~450-pixel
  // rim changes at most half a pixel each, 1.4% of the disk: allow 2% relative.
  EXPECT_NEAR(fraction, expected_fraction, 0.02 * expected_fraction);
}

TEST_F(PreviewRendererTest, MultisamplingBlendsEdgesOnlyWhenAsked) {
  const Mesh mesh = square(0.5f, 0.3f);  // rotated: edges cross pixels
  auto blended_pixels = [&](int samples) {
    const PreviewOptions options = options_for(64, samples, orthographic_front());
    Image image(64, 64);
    renderer_.render(mesh.view(), options, image.rgba);
    const glm::ivec4 background = to_bytes(options.background), inside = image.at(32, 32);
    int blended = 0;
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) {
        const glm::ivec4 p = image.at(x, y);
        // More than one 8-bit step away from both the background and the square's colour.
        blended += glm::any(glm::greaterThan(glm::abs(p - background), glm::ivec4(1))) &&
                   glm::any(glm::greaterThan(glm::abs(p - inside), glm::ivec4(1)));
      }
    return blended;
  };
  EXPECT_EQ(blended_pixels(1), 0);
  EXPECT_GT(blended_pixels(4), 20);  // the rim is ~180 pixels long
}

TEST_F(PreviewRendererTest, MannequinFromTheDefaultCameraIsFramedAndCentred) {
  const deform::Model model = mannequin::make_mannequin({5000});
  constexpr int kSize = 200;
  const PreviewOptions options = options_for(kSize, 4);
  Image image(kSize, kSize);
  renderer_.render({model.positions, model.normals, model.indices, {}}, options, image.rgba);
  const glm::ivec4 background = to_bytes(options.background);
  for (auto [x, y] : {std::pair{0, 0}, {kSize - 1, 0}, {0, kSize - 1}, {kSize - 1, kSize - 1}}) {
    EXPECT_EQ(image.at(x, y), background) << "corner " << x << "," << y;
  }
  EXPECT_NE(image.at(kSize / 2, kSize / 2), background);  // the torso
  int top = kSize, bottom = -1, left = kSize, right = -1;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x)
      if (image.at(x, y) != background) {
        top = std::min(top, y), bottom = std::max(bottom, y);
        left = std::min(left, x), right = std::max(right, x);
      }
  const double fraction = image.count_not(background) / double(kSize * kSize);
  std::printf("silhouette rows %d..%d, columns %d..%d, %.3f of the image\n", top, bottom, left,
              right, fraction);
  // The bounding sphere (radius r) is tangent to the 30° view, which is 2r / cos 15° tall at
  // the centre: a 1.75 m figure in a 1.75 x ~1.2 x ~0.3 m A-pose box (r ~ 1.07 m) spans about
  // 1.75 cos 15° / 2r ~ 79% of the height; allow 60..85% for the box's exact size. The figure
  // is symmetric about x = 0 and the box is centred: margins equal within 2% of the image.
  EXPECT_GE(bottom - top, 0.60 * kSize);
  EXPECT_LE(bottom - top, 0.85 * kSize);
  EXPECT_NEAR(left, kSize - 1 - right, 0.02 * kSize);
  EXPECT_NEAR((top + bottom) / 2.0, kSize / 2.0, 0.02 * kSize);
  // A thin human shape fills well under half of its box: between 5% and 40% of the image.
  EXPECT_GT(fraction, 0.05);
  EXPECT_LT(fraction, 0.40);
  // The image goes to PNG as is (top row first).
  std::vector<std::uint8_t> png;
  io::encode_png(kSize, kSize, image.rgba, png);
  EXPECT_GT(png.size(), 100u);
}

TEST_F(PreviewRendererTest, RejectsInputsThatDoNotFitTogether) {
  Mesh mesh = square(0.5f);
  Image image(16, 16);
  EXPECT_NE(renderer_.validate(mesh.view(), options_for(32, 1), image.rgba).find("W*H*4"),
            std::string::npos);
  mesh.normals.pop_back();
  EXPECT_NE(renderer_.validate(mesh.view(), options_for(16, 1), image.rgba).find("normals"),
            std::string::npos);
  EXPECT_THROW(renderer_.render(mesh.view(), options_for(16, 1), image.rgba),
               std::invalid_argument);
  mesh = square(0.5f);
  EXPECT_NE(renderer_.validate(mesh.view(), options_for(16, 0), image.rgba).find("samples"),
            std::string::npos);
  EXPECT_EQ(renderer_.validate(mesh.view(), options_for(16, 1), image.rgba), "");
}

}  // namespace
}  // namespace sweepd::gpu::preview_renderer_test
