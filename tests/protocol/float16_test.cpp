// Tests for protocol/float16.h: binary16 conversion used by compact PosedVertices.
#include "protocol/float16.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace sweepd::protocol {
namespace {

bool is_half_nan(std::uint16_t half) { return (half & 0x7c00u) == 0x7c00u && (half & 0x3ffu); }

TEST(Float16, EveryHalfSurvivesDecodeThenEncodeExactly) {
  // Every non-NaN binary16 value is representable in float32, so the round trip must give the
  // identical bit pattern (tolerance 0: exactness is the claim). NaNs must stay NaN.
  int mismatches = 0;
  for (std::uint32_t bits = 0; bits <= 0xffffu; ++bits) {
    const auto half = static_cast<std::uint16_t>(bits);
    const float value = half_to_float(half);
    if (is_half_nan(half)) {
      EXPECT_TRUE(std::isnan(value)) << std::hex << bits;
      EXPECT_TRUE(is_half_nan(float_to_half(value))) << std::hex << bits;
      continue;
    }
    if (float_to_half(value) != half) ++mismatches;
  }
  EXPECT_EQ(mismatches, 0);
}

TEST(Float16, KnownValuesFromTheIeeeFormat) {
  EXPECT_EQ(float_to_half(1.0f), 0x3c00u);
  EXPECT_EQ(float_to_half(-2.0f), 0xc000u);
  EXPECT_EQ(float_to_half(65504.0f), 0x7bffu);               // largest finite half
  EXPECT_EQ(float_to_half(65519.0f), 0x7bffu);               // below the rounding midpoint
  EXPECT_EQ(float_to_half(65520.0f), 0x7c00u);               // the midpoint rounds to infinity
  EXPECT_EQ(float_to_half(std::ldexp(1.0f, -24)), 0x0001u);  // smallest subnormal
  EXPECT_EQ(float_to_half(std::ldexp(1.0f, -25)), 0x0000u);  // tie with zero: to even (zero)
  EXPECT_EQ(float_to_half(std::ldexp(1.0001f, -25)), 0x0001u);
  EXPECT_EQ(float_to_half(-0.0f), 0x8000u);
  // Ties to even in the normal range: 1 + 2^-11 lies halfway between 1 and 1 + 2^-10.
  EXPECT_EQ(float_to_half(1.0f + std::ldexp(1.0f, -11)), 0x3c00u);
  EXPECT_EQ(float_to_half(1.0f + 3.0f * std::ldexp(1.0f, -11)), 0x3c02u);
  EXPECT_EQ(half_to_float(0x3555u), 0.333251953125f);  // 0x3555 = 1365/4096
}

#if defined(__FLT16_MAX__)
TEST(Float16, MatchesTheCompilersConversionOnRandomFloats) {
  // GCC's _Float16 conversion (libgcc, round to nearest even) is an independent reference;
  // bit patterns are drawn uniformly so every exponent range, subnormals and overflow occur.
  std::mt19937 random(7);
  int mismatches = 0;
  for (int i = 0; i < 1'000'000; ++i) {
    const float value = std::bit_cast<float>(static_cast<std::uint32_t>(random()));
    if (std::isnan(value)) continue;
    const auto reference = std::bit_cast<std::uint16_t>(static_cast<_Float16>(value));
    if (float_to_half(value) != reference) ++mismatches;
  }
  EXPECT_EQ(mismatches, 0);
}
#endif

TEST(Float16, SpanConversionsAgreeWithTheScalarOnesOnEveryKindOfValue) {
  // The span versions take a vectorised path for normal numbers and fall back per block:
  // every half bit pattern (zeros, subnormals, inf, NaN among them) plus random float bit
  // patterns (overflow, underflow, NaN), in a length that ends mid-block, must give the
  // scalar functions' exact bits.
  std::vector<std::uint16_t> every_half(0x10000 + 37);
  for (std::size_t i = 0; i < every_half.size(); ++i) every_half[i] = static_cast<std::uint16_t>(i);
  std::vector<float> decoded(every_half.size());
  decode_float16(every_half, decoded);
  int decode_mismatches = 0;
  for (std::size_t i = 0; i < every_half.size(); ++i) {
    const float scalar = half_to_float(every_half[i]);
    if (std::bit_cast<std::uint32_t>(decoded[i]) != std::bit_cast<std::uint32_t>(scalar)) {
      ++decode_mismatches;
    }
  }
  EXPECT_EQ(decode_mismatches, 0);

  std::mt19937 random(5);
  std::vector<float> floats = decoded;
  for (int i = 0; i < 100'000; ++i)
    floats.push_back(std::bit_cast<float>(static_cast<std::uint32_t>(random())));
  std::vector<std::uint16_t> encoded(floats.size());
  encode_float16(floats, encoded);
  int encode_mismatches = 0;
  for (std::size_t i = 0; i < floats.size(); ++i) {
    if (encoded[i] != float_to_half(floats[i])) ++encode_mismatches;
  }
  EXPECT_EQ(encode_mismatches, 0);
}

TEST(Float16, SpanConversionOfPositionsStaysWithinHalfAnUlp) {
  std::mt19937 random(11);
  std::uniform_real_distribution<float> metres(-2.0f, 2.0f);
  std::vector<float> positions(3000);
  for (float& p : positions) p = metres(random);
  std::vector<std::uint16_t> halves(positions.size());
  std::vector<float> decoded(positions.size());
  encode_float16(positions, halves);
  decode_float16(halves, decoded);
  for (std::size_t i = 0; i < positions.size(); ++i) {
    // Round to nearest: error at most half an ulp, 2^-11 relative for normal halves
    // (values here are above 2^-14 except a handful near 0, covered by the 2^-25 floor).
    const float bound =
        std::max(std::abs(positions[i]) * std::ldexp(1.0f, -11), std::ldexp(1.0f, -25));
    EXPECT_LE(std::abs(decoded[i] - positions[i]), bound) << positions[i];
    EXPECT_EQ(halves[i], float_to_half(positions[i]));
  }
}

}  // namespace
}  // namespace sweepd::protocol
