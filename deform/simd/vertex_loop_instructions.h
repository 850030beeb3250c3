// VertexLoopInstructions: which instructions a per-vertex loop runs, chosen at run time (one
// binary for every x86-64 CPU): the baseline's (SSE2 on x86-64, NEON on ARM64) or AVX2 + FMA.
#pragma once

namespace sweepd::deform {

enum class VertexLoopInstructions { kBaseline, kAvx2Fma };

// kAvx2Fma on an x86-64 CPU that has AVX2 and FMA, else kBaseline.
inline VertexLoopInstructions widest_vertex_loop_instructions() {
#if defined(__x86_64__)
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"))
    return VertexLoopInstructions::kAvx2Fma;
#endif
  return VertexLoopInstructions::kBaseline;
}

}  // namespace sweepd::deform
