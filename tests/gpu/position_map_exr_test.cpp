// End to end on the procedural mannequin: GPU position map (llvmpipe in CI) → io::encode_exr →
// read back with OpenEXR's InputFile → at every vertex's UV texel, the position the vertex's
// triangles interpolate there; coverage matching the UV charts' area; header attributes.
#include "tests/io/position_map_exr.h"

#include <ImfChannelList.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfIntAttribute.h>
#include <ImfStringAttribute.h>
#include <gtest/gtest.h>

#include <cstring>
#include <glm/gtc/matrix_transform.hpp>
#include <vector>

#include "gpu/position_map_renderer.h"
#include "io/exr/exr_write.h"
#include "mannequin/mannequin.h"
#include "tests/gpu/uv_reference.h"
#include "tests/io/exr_memory_stream.h"

namespace sweepd::gpu {
namespace {

using ReadBack = io::test_support::DecodedPositionMap;

ReadBack read_position_map(const std::vector<std::uint8_t>& bytes, Imf::Header& header_out) {
  io::test_support::ExrMemoryStream stream(bytes);
  Imf::InputFile file(stream);
  header_out = file.header();
  return io::test_support::decode_position_map(file);
}

class MannequinPositionMap : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { model_ = new deform::Model(mannequin::make_mannequin({20000})); }
  static void TearDownTestSuite() { delete model_; }

  // Renders at size x size, encodes as EXR (ZIP), reads it back.
  ReadBack render_and_read(int size, std::span<const glm::vec3> positions, const char* space,
                           Imf::Header& header) {
    PositionMapRenderer renderer(context_);
    std::vector<float> p(size * size * 3), n(size * size * 3), a(size * size);
    renderer.render({model_->uvs, positions, model_->normals, model_->indices},
                    {.width = size, .height = size, .gutter_pixels = 4, .view = std::nullopt},
                    {p, n, a});
    io::ExrOptions options;
    options.model = model_->name;
    options.frame = 3;
    options.pose_hash = 0xfeedull;
    options.space = space;
    std::vector<std::uint8_t> bytes;
    io::encode_exr({size, size, p, n, a}, options, bytes);
    return read_position_map(bytes, header);
  }

  static deform::Model* model_;
  Context context_;
};
deform::Model* MannequinPositionMap::model_ = nullptr;

TEST_F(MannequinPositionMap, ExrHoldsTheVertexPositionsAtTheirUvTexels) {
  ASSERT_TRUE(model_->has_uvs());
  constexpr int kSize = 1024;
  Imf::Header header;
  const ReadBack map = render_and_read(kSize, model_->positions, "object", header);
  ASSERT_EQ(map.width, kSize);
  EXPECT_EQ(header.typedAttribute<Imf::StringAttribute>("model").value(), model_->name);
  EXPECT_EQ(header.typedAttribute<Imf::IntAttribute>("frame").value(), 3);
  EXPECT_EQ(header.typedAttribute<Imf::StringAttribute>("poseHash").value(), "000000000000feed");
  EXPECT_EQ(header.typedAttribute<Imf::StringAttribute>("space").value(), "object");
  EXPECT_EQ(header.typedAttribute<Imf::StringAttribute>("units").value(), "metres");
  EXPECT_NE(header.channels().findChannel("N.X"), nullptr);

  const auto check = test_reference::check_vertex_texels(
      model_->uvs, model_->positions, model_->indices, {kSize, kSize, map.positions, map.coverage});
  std::printf("checked %d of %zu vertices (%d in overlapping UVs), worst error / tolerance %.3f\n",
              check.checked, model_->vertex_count(), check.overlapping,
              check.worst_error_over_tolerance);
  // Every vertex is checked: the mannequin's UV charts neither fold nor overlap (uv_atlas.h),
  // so no texel centre lies inside two triangles.
  EXPECT_EQ(check.overlapping, 0);
  EXPECT_EQ(check.checked, static_cast<int>(model_->vertex_count()));
  EXPECT_EQ(check.covered_mismatch, 0);
  EXPECT_EQ(check.value_mismatch, 0);
  for (const std::string& mismatch : check.mismatches) ADD_FAILURE() << mismatch;

  int covered = 0;
  for (float a : map.coverage) covered += a == 1.0f;
  const auto expected =
      test_reference::expected_coverage(model_->uvs, model_->indices, kSize, kSize);
  std::printf("covered %d texels, expected %.0f +- %.0f\n", covered, expected.texels,
              expected.tolerance);
  EXPECT_NEAR(covered, expected.texels, expected.tolerance);
}

TEST_F(MannequinPositionMap, CameraSpaceMapHoldsViewTransformedPositions) {
  constexpr int kSize = 512;
  const glm::mat4 view =
      glm::lookAt(glm::vec3(0.5f, 1.2f, 3.0f), glm::vec3(0.0f, 0.9f, 0.0f), glm::vec3(0, 1, 0));
  std::vector<glm::vec3> in_camera;
  for (const glm::vec3& p : model_->positions)
    in_camera.push_back(glm::vec3(view * glm::vec4(p, 1)));
  PositionMapRenderer renderer(context_);
  std::vector<float> p(kSize * kSize * 3), a(kSize * kSize);
  renderer.render({model_->uvs, model_->positions, {}, model_->indices},
                  {.width = kSize, .height = kSize, .gutter_pixels = 0, .view = view}, {p, {}, a});
  // The GPU transforms the vertices, then interpolates: compare with interpolating the
  // CPU-transformed vertices (same tolerance model).
  const auto check = test_reference::check_vertex_texels(model_->uvs, in_camera, model_->indices,
                                                         {kSize, kSize, p, a});
  std::printf("checked %d vertices, worst error / tolerance %.3f\n", check.checked,
              check.worst_error_over_tolerance);
  EXPECT_LT(check.overlapping, static_cast<int>(0.01 * model_->vertex_count()));
  EXPECT_EQ(check.covered_mismatch, 0);
  EXPECT_EQ(check.value_mismatch, 0);
  for (const std::string& mismatch : check.mismatches) ADD_FAILURE() << mismatch;
}

}  // namespace
}  // namespace sweepd::gpu
