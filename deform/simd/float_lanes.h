// FloatLanes: four floats in one SIMD register, for the per-vertex skinning loops.
//
// A GCC/Clang vector extension: +, -, * work lane by lane, and a float operand is broadcast to
// all four lanes, so x86-64 (SSE) and ARM64 (NEON) compile the same code to 4-wide arithmetic
// without target flags. load_lanes reads any four consecutive floats (no alignment needed).
// FloatLanes8: eight floats, one AVX register where the function is compiled for AVX, two
// FloatLanes otherwise. Use it inside functions only (passing it by value changes the ABI with
// the target, so GCC warns).
#pragma once

#include <cstring>

namespace sweepd::deform {

typedef float FloatLanes __attribute__((vector_size(16)));
typedef float FloatLanes8 __attribute__((vector_size(32)));

// Four floats starting at `first` (e.g. a glm::vec4 or glm::quat, or a glm::mat4 column).
inline FloatLanes load_lanes(const float* first) {
  FloatLanes lanes;
  std::memcpy(&lanes, first, sizeof(lanes));
  return lanes;
}

inline float sum_of_lanes(FloatLanes lanes) {
  return (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]);
}

}  // namespace sweepd::deform
