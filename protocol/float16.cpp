#include "protocol/float16.h"

#include <bit>
#include <cassert>
#include <cstddef>

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

void encode_float16(std::span<const float> values, std::span<std::uint16_t> halves) {
  assert(values.size() == halves.size());
  for (std::size_t i = 0; i < values.size(); ++i) halves[i] = float_to_half(values[i]);
}

void decode_float16(std::span<const std::uint16_t> halves, std::span<float> values) {
  assert(values.size() == halves.size());
  for (std::size_t i = 0; i < halves.size(); ++i) values[i] = half_to_float(halves[i]);
}

}  // namespace sweepd::protocol
