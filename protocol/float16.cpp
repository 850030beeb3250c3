#include "protocol/float16.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cstddef>
#include <cstring>

namespace sweepd::protocol {
namespace {

constexpr std::uint32_t kFloatInfinity = 0x7f800000u;
constexpr std::uint32_t kHalfOverflow = 0x477ff000u;        // 65520: rounds to infinity
constexpr std::uint32_t kHalfSmallestNormal = 0x38800000u;  // 2^-14
constexpr std::uint32_t kHalfUnderflow = 0x33000000u;       // 2^-25: a tie that rounds to 0

// Shifts `bits` right by `shift`, rounding to nearest with ties to even.
std::uint32_t shift_round_even(std::uint32_t bits, int shift) {
  const std::uint32_t kept = bits >> shift;
  const std::uint32_t remainder = bits & ((1u << shift) - 1u);
  const std::uint32_t half_way = 1u << (shift - 1);
  const bool round_up = remainder > half_way || (remainder == half_way && (kept & 1u));
  return kept + (round_up ? 1u : 0u);
}

}  // namespace

std::uint16_t float_to_half(float value) {
  const std::uint32_t bits = std::bit_cast<std::uint32_t>(value);
  const std::uint32_t sign = (bits >> 16) & 0x8000u;
  const std::uint32_t magnitude = bits & 0x7fffffffu;
  if (magnitude >= kFloatInfinity) {  // infinity or NaN (a NaN keeps its top payload, quieted)
    const std::uint32_t nan_payload =
        magnitude > kFloatInfinity ? (0x200u | ((magnitude >> 13) & 0x3ffu)) : 0u;
    return static_cast<std::uint16_t>(sign | 0x7c00u | nan_payload);
  }
  if (magnitude >= kHalfOverflow) return static_cast<std::uint16_t>(sign | 0x7c00u);
  if (magnitude < kHalfSmallestNormal) {
    if (magnitude <= kHalfUnderflow) return static_cast<std::uint16_t>(sign);
    // Subnormal half: the value in units of 2^-24.
    const std::uint32_t mantissa = (magnitude & 0x7fffffu) | 0x800000u;
    const int exponent = static_cast<int>(magnitude >> 23);
    return static_cast<std::uint16_t>(sign | shift_round_even(mantissa, 126 - exponent));
  }
  // Normal half: rebias the exponent (127 → 15) and round the mantissa from 23 to 10 bits;
  // a carry out of the mantissa correctly bumps the exponent.
  return static_cast<std::uint16_t>(sign | shift_round_even(magnitude - 0x38000000u, 13));
}

float half_to_float(std::uint16_t half) {
  const std::uint32_t sign = static_cast<std::uint32_t>(half & 0x8000u) << 16;
  const std::uint32_t exponent = (half >> 10) & 0x1fu;
  std::uint32_t mantissa = half & 0x3ffu;
  if (exponent == 0x1fu) return std::bit_cast<float>(sign | kFloatInfinity | (mantissa << 13));
  if (exponent != 0) {
    return std::bit_cast<float>(sign | ((exponent + 112u) << 23) | (mantissa << 13));
  }
  if (mantissa == 0) return std::bit_cast<float>(sign);
  // Subnormal half: normalise into a float exponent.
  std::uint32_t float_exponent = 113u;
  while ((mantissa & 0x400u) == 0) {
    mantissa <<= 1;
    --float_exponent;
  }
  return std::bit_cast<float>(sign | (float_exponent << 23) | ((mantissa & 0x3ffu) << 13));
}

// The span versions convert blocks of values in a branch-free loop the compiler vectorises
// (normal numbers both ways), then redo the rare others in that block (zero, subnormal,
// overflow, inf, NaN) with the scalar functions: same results, several times faster.
constexpr std::size_t kBlock = 256;

bool encodes_to_normal_half(std::uint32_t magnitude) {
  return magnitude - kHalfSmallestNormal < kHalfOverflow - kHalfSmallestNormal;
}

// Exponent 1..30: a normal half (0 is zero or subnormal, 31 infinity or NaN).
bool decodes_from_normal_half(std::uint32_t exponent) { return exponent - 1u < 30u; }

void encode_float16(std::span<const float> values, std::span<std::uint16_t> halves) {
  assert(values.size() == halves.size());
  for (std::size_t start = 0; start < values.size(); start += kBlock) {
    const std::size_t end = std::min(values.size(), start + kBlock);
    std::uint32_t any_special = 0;
    for (std::size_t i = start; i < end; ++i) {
      const std::uint32_t bits = std::bit_cast<std::uint32_t>(values[i]);
      const std::uint32_t magnitude = bits & 0x7fffffffu;
      const std::uint32_t rebiased = magnitude - 0x38000000u;
      const std::uint32_t kept = rebiased >> 13;
      const std::uint32_t remainder = rebiased & 0x1fffu;
      const std::uint32_t round_up =
          static_cast<std::uint32_t>(remainder > 0x1000u) | ((remainder == 0x1000u) & kept);
      halves[i] = static_cast<std::uint16_t>(((bits >> 16) & 0x8000u) | (kept + round_up));
      any_special |= static_cast<std::uint32_t>(!encodes_to_normal_half(magnitude));
    }
    if (any_special == 0) continue;
    for (std::size_t i = start; i < end; ++i) {
      if (!encodes_to_normal_half(std::bit_cast<std::uint32_t>(values[i]) & 0x7fffffffu)) {
        halves[i] = float_to_half(values[i]);
      }
    }
  }
}

void decode_float16(std::span<const std::uint16_t> halves, std::span<float> values) {
  assert(values.size() == halves.size());
  std::uint32_t bits[kBlock];  // float bit patterns, copied out whole (vectorises; no aliasing)
  for (std::size_t start = 0; start < halves.size(); start += kBlock) {
    const std::size_t count = std::min(halves.size() - start, kBlock);
    std::uint32_t any_special = 0;
    for (std::size_t k = 0; k < count; ++k) {
      const std::uint32_t half = halves[start + k];
      const std::uint32_t exponent = (half >> 10) & 0x1fu;
      bits[k] = ((half & 0x8000u) << 16) | (((half & 0x7fffu) << 13) + (112u << 23));
      any_special |= static_cast<std::uint32_t>(!decodes_from_normal_half(exponent));
    }
    std::memcpy(values.data() + start, bits, count * sizeof(float));
    if (any_special == 0) continue;
    for (std::size_t i = start; i < start + count; ++i) {
      if (!decodes_from_normal_half((halves[i] >> 10) & 0x1fu))
        values[i] = half_to_float(halves[i]);
    }
  }
}

}  // namespace sweepd::protocol
