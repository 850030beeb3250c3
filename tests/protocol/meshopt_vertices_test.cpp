// Tests for protocol/meshopt_vertices.h: the Meshopt position format's encoder and decoders, and
// PosedVertices frames carrying it through copy_positions / copy_normals.
#include "protocol/meshopt_vertices.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "protocol/messages.h"

namespace sweepd::protocol {
namespace {

// n points in a 2 m box, shifted off the origin (the grid's origin is their minimum, not 0).
std::vector<float> random_positions(std::size_t n, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> coordinate(-1.0f, 1.0f);
  std::vector<float> values(3 * n);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = coordinate(random) + 0.5f * (i % 3);
  return values;
}

std::vector<float> random_unit_normals(std::size_t n, unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<float> gaussian;
  std::vector<float> values(3 * n);
  for (std::size_t v = 0; v < n; ++v) {
    const float x = gaussian(random), y = gaussian(random), z = gaussian(random);
    const float length = std::sqrt(x * x + y * y + z * z);
    values[3 * v] = x / length, values[3 * v + 1] = y / length, values[3 * v + 2] = z / length;
  }
  return values;
}

float max_difference(const std::vector<float>& a, const std::vector<float>& b) {
  float worst = 0.0f;
  for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(a[i] - b[i]));
  return worst;
}

// Half the 0.18 mm step, plus float32 rounding of origin + step * q near 2 m (a few 1e-7 m).
constexpr float kPositionTolerance = 0.5f * kMeshoptPositionStep + 1e-6f;
// Half a step of 1/127, plus float32 rounding.
constexpr float kNormalTolerance = 0.5f / 127.0f + 1e-6f;

TEST(MeshoptVertices, PositionsAndNormalsComeBackWithinHalfAStep) {
  const std::vector<float> positions = random_positions(5000, 1);
  const std::vector<float> normals = random_unit_normals(5000, 2);
  MeshoptEncoder encoder;
  const PositionGrid grid = encoder.encode(positions, normals);
  EXPECT_FLOAT_EQ(grid.step, kMeshoptPositionStep);
  float lowest_y = positions[1];
  for (std::size_t i = 1; i < positions.size(); i += 3) lowest_y = std::min(lowest_y, positions[i]);
  EXPECT_EQ(grid.origin.y(), lowest_y);
  std::vector<float> decoded(positions.size()), decoded_normals(normals.size());
  ASSERT_TRUE(decode_meshopt_positions(encoder.positions(), grid, decoded));
  ASSERT_TRUE(decode_meshopt_normals(encoder.normals(), decoded_normals));
  EXPECT_LE(max_difference(decoded, positions), kPositionTolerance);
  EXPECT_LE(max_difference(decoded_normals, normals), kNormalTolerance);
}

TEST(MeshoptVertices, EncodingTheSameInputTwiceGivesTheSameBytes) {
  // Stateless: a reply depends on its own positions only, whatever was encoded before.
  const std::vector<float> first = random_positions(300, 3), second = random_positions(900, 4);
  MeshoptEncoder reused, fresh;
  reused.encode(first, {});
  reused.encode(second, {});
  fresh.encode(second, {});
  EXPECT_TRUE(std::ranges::equal(reused.positions(), fresh.positions()));
  EXPECT_TRUE(reused.normals().empty());
}

TEST(MeshoptVertices, TruncatedOrForeignBytesAreRefused) {
  const std::vector<float> positions = random_positions(1000, 5);
  MeshoptEncoder encoder;
  const PositionGrid grid = encoder.encode(positions, {});
  std::vector<float> decoded(positions.size());
  const auto bytes = encoder.positions();
  EXPECT_FALSE(decode_meshopt_positions(bytes.first(bytes.size() - 1), grid, decoded));
  EXPECT_FALSE(decode_meshopt_positions({}, grid, decoded));
  std::vector<float> not_triples(10);
  EXPECT_FALSE(decode_meshopt_normals(encoder.positions(), not_triples));
  // 12-byte position vertices read as 4-byte normal vertices leave bytes over.
  EXPECT_FALSE(decode_meshopt_normals(encoder.positions(), decoded));
}

TEST(MeshoptVertices, NonFiniteCoordinatesBecomeTheOriginAndLeaveTheGridAlone) {
  std::vector<float> positions = {0.5f,  1.0f,
                                  2.0f,  std::numeric_limits<float>::quiet_NaN(),
                                  -3.0f, std::numeric_limits<float>::infinity()};
  MeshoptEncoder encoder;
  const PositionGrid grid = encoder.encode(positions, {});
  EXPECT_EQ(grid.origin.x(), 0.5f);
  EXPECT_EQ(grid.origin.y(), -3.0f);
  EXPECT_EQ(grid.origin.z(), 2.0f);
  std::vector<float> decoded(positions.size());
  ASSERT_TRUE(decode_meshopt_positions(encoder.positions(), grid, decoded));
  EXPECT_EQ(decoded[3], 0.5f);  // NaN x: the origin's x
  EXPECT_EQ(decoded[5], 2.0f);  // infinite z: the origin's z
}

TEST(MeshoptVertices, PosedVerticesFramesCarryTheStreamsAndTheGrid) {
  const std::size_t n = 2000;
  const std::vector<float> positions = random_positions(n, 6);
  const std::vector<float> normals = random_unit_normals(n, 7);
  MeshoptEncoder encoder;
  PosedVerticesHeader header{.request_id = 3,
                             .model_id = 9,
                             .sequence = 11,
                             .vertex_count = static_cast<std::uint32_t>(n),
                             .format = PositionFormat::Meshopt,
                             .normals = true};
  header.grid = encoder.encode(positions, normals);
  header.meshopt_positions_bytes = encoder.positions().size();
  header.meshopt_normals_bytes = encoder.normals().size();
  flatbuffers::FlatBufferBuilder builder;
  PosedVerticesFrame frame(builder, header);
  ASSERT_EQ(frame.positions_meshopt().size(), encoder.positions().size());
  EXPECT_TRUE(frame.positions_f32().empty() && frame.positions_f16().empty());
  std::ranges::copy(encoder.positions(), frame.positions_meshopt().begin());
  std::ranges::copy(encoder.normals(), frame.normals_meshopt().begin());

  const auto bytes = frame.bytes();
  flatbuffers::Verifier verifier(bytes.data(), bytes.size());
  ASSERT_TRUE(VerifySizePrefixedMessageBuffer(verifier));
  const auto* reply = GetSizePrefixedMessage(bytes.data())->body_as_PosedVertices();
  ASSERT_NE(reply, nullptr);
  EXPECT_EQ(reply->positions_f32(), nullptr);
  EXPECT_FLOAT_EQ(reply->position_step(), kMeshoptPositionStep);
  std::vector<float> decoded(3 * n), decoded_normals(3 * n);
  ASSERT_TRUE(copy_positions(*reply, decoded));
  ASSERT_TRUE(copy_normals(*reply, decoded_normals));
  EXPECT_LE(max_difference(decoded, positions), kPositionTolerance);
  EXPECT_LE(max_difference(decoded_normals, normals), kNormalTolerance);
  std::vector<float> wrong_size(3 * n - 3);
  EXPECT_FALSE(copy_positions(*reply, wrong_size));
}

}  // namespace
}  // namespace sweepd::protocol
