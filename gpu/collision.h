// CollisionDetector: self-intersection of a skin region on the GPU (paper §4.3) — the same
// intersecting triangle pairs as deform::SelfIntersectionDetector, found by a GL 4.5 compute
// shader on a gpu::Context.
//
// detect
//   Inputs:  positions  #V posed vertex positions
//            indices    3 per mesh triangle (seam-welded, e.g. CollisionRegions::welded_indices);
//                       triangles that share an index are neighbours and never reported
//            triangles  #T ids of the triangles to test against each other (a few thousand)
//   Output:  pairs      {first < second} triangle ids whose closed triangles meet, sorted,
//                       unique; cleared first.
// Broad phase: sort and sweep along x — the triangles are uploaded sorted by their boxes'
// lower x; one invocation per triangle tests the boxes of the later ones until one starts past
// its own upper x (at worst #T²/2 box tests); narrow phase: the Guigue–Devillers test of
// deform/features/triangle_intersection.h, transcribed to GLSL with the same double-precision
// operations in the same order (`precise`, so no fused multiply-adds), so the pairs are
// bit-identical to the CPU reference. Construct, call and destroy on the context's thread
// (gpu::Worker jobs); the Context must outlive the detector. GL buffers are kept and grown between
// calls. last_timings(): the last detect's upload (sorting the boxes and writing the buffers, CPU
// clock) and readback (from the dispatch to the pairs in hand: the wait for the compute
// shader is in it, as GL gives no cheaper split without timer queries).
#pragma once

#include <chrono>
#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "deform/features/self_intersection.h"
#include "gpu/egl_context.h"
#include "gpu/shader_program.h"

namespace sweepd::gpu {

struct CollisionTimings {
  std::chrono::nanoseconds upload{0}, readback{0};
};

class CollisionDetector {
 public:
  explicit CollisionDetector(const Context& context);
  ~CollisionDetector();
  CollisionDetector(const CollisionDetector&) = delete;
  CollisionDetector& operator=(const CollisionDetector&) = delete;

  void detect(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
              std::span<const std::uint32_t> triangles, std::vector<deform::TrianglePair>& pairs);
  const CollisionTimings& last_timings() const { return timings_; }

 private:
  const GlFunctions& gl_;
  ShaderProgram program_;
  GLuint buffers_[4] = {0, 0, 0, 0};  // corners, triangle records, pair count, pairs
  std::size_t pair_capacity_ = 0;
  std::vector<glm::vec4> corners_;
  std::vector<glm::uvec4> records_;
  std::vector<glm::uvec2> found_;
  std::vector<std::pair<float, std::uint32_t>> order_;  // (box lower x, triangle id)
  CollisionTimings timings_;
};

}  // namespace sweepd::gpu
