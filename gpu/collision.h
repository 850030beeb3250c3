// CollisionDetector: self-intersection of skin triangle lists on the GPU (paper §4.3) — the same
// intersecting triangle pairs as deform::SelfIntersectionDetector, for collision regions and for
// a whole-body list, found by GL 4.5 compute passes on a gpu::Context.
//
// detect(positions, indices, triangles, pairs)
//   Inputs:  positions  #V posed vertex positions
//            indices    3 per mesh triangle (seam-welded, e.g. CollisionRegions::welded_indices);
//                       triangles that share an index are neighbours and never reported
//            triangles  #T ids of the triangles to test against each other (a region, or the
//                       whole body)
//   Output:  pairs      {first < second} triangle ids whose closed triangles meet, sorted,
//                       unique; cleared first.
// detect_all(positions, indices, lists, pairs): the same for L lists at once (pairs: L vectors,
//   pairs[l] for lists[l]), in one submission.
//
// Pipeline. Topology (each list's triangle ids and welded corners) is uploaded once, when the
// detector first meets the list, into persistent buffers; later calls check it against the
// caller's (ids and corners compared on the CPU, O(#T)) and reuse it. Per submission the posed
// positions go up once, every stale list is processed by the same six dispatches, and the pairs
// of all of them come back in one read (counters and pairs in one buffer). No allocation, no
// shader compilation per call once warm (programs are compiled by the constructor).
//   Broad phase: a spatial hash built by counting sort. Per list a cell size (twice the mean of
//   its triangles' largest box extents, at least 1/16 of the largest — the CPU computes it
//   while it checks the list's positions); each triangle's box enters every cell it covers; bucket
//   counts -> one scan per workgroup with one atomic per group -> scatter; then every entry
//   meets the later entries of its bucket with the same cell and list, and a box pair counts
//   only in the cell holding its overlap's lower corner (the CPU reference's rule), so each
//   pair is tested once. Chosen over a Karras LBVH for llvmpipe, where the passes run as SIMD
//   loops on the CPU's cores: the hash has no sort passes (an LBVH's radix sort alone is 8-16
//   dispatches) and no divergent stack traversal; its cost per list is a few short loops per
//   triangle.
//   Narrow phase: Guigue–Devillers in float on the same determinants, with the same arguments,
//   as deform/features/triangle_intersection.cpp, each sign certified by Shewchuk's orient3d
//   error bound. For a determinant evaluated in rounded arithmetic with unit roundoff ε from
//   the float corners (differences, 2×2 minors, dot product, in that order) Shewchuk shows
//   |det_computed − det_exact| ≤ (7 + 56ε)ε · P, P the permanent (the same expression on
//   absolute values, also rounded). With ε_f = 2^-24 and the CPU's doubles (ε_d = 2^-53,
//   P_d ≤ P_f(1 + 6ε_f)): |det_f| > 2^-21 · P_f ≥ err_f + err_d ⇒ det_exact has det_f's sign
//   and is further from 0 than the CPU's rounding ⇒ the CPU's double has that sign too (and is
//   not 0). 1e-30 is added to the bound for products a GPU flushes to zero (coordinates up to
//   1e6 m). With every sign the CPU's path reads certified, the GPU takes the CPU's branches and
//   gives its answer; a pair with a sign it cannot certify (touching, coplanar, 1e-7 m near
//   misses at metre scale) is "undecided" and goes to the CPU's exact test
//   (deform::triangles_intersect) after the read — a handful per frame on posed skin.
//   Lists holding a non-finite position run on the CPU reference.
// Batching. A call whose list's corners still hold the positions of its last computation gets
// that computation's pairs back with no GPU work. Otherwise the list is recomputed, and with it
// every other list last computed from the same positions buffer (same data pointer) that has
// gone stale too and holds at most a quarter of the mesh's triangles (regions, not a whole
// body): so CollisionFeatures' per-region calls cost one submission for all regions at a
// frame's first detection, and one per fold round after it. Up to 64 lists are kept (then the
// cache starts over).
//
// Measured (bench/collision_bench, BM_RegionsPerFrame, the 8 regions per frame at 150° elbow and
// knee flexion; llvmpipe on a 2-core machine shared with other builds, load average 5-10): on
// the shared male (6,647 region triangles) 7.9 ms of one core's time with llvmpipe kept on the
// calling thread (LP_NUM_THREADS=0) against 5.3 ms for the CPU reference (1.5×; the detector
// this replaces, one dispatch and one wait per region, all in double: 239 ms, 37×), 9.0 ms
// wall with llvmpipe's 2 threads against 9.8 ms; on the 72k mannequin (96k region triangles)
// 118-141 ms against 78 ms one core (1.5-1.8×), 137 ms wall against 142 ms. Most of it is the
// cell-pair pass; the CPU side (topology checks, positions, the undecided pairs) is 0.1 ms
// (1.5-2.5 ms on the mannequin). README.md ("The GPU pipeline") has the table.
//
// Construct, call and destroy on the context's thread (gpu::Worker jobs); the Context must
// outlive the detector. last_timings(): the last call's upload (checking and uploading, CPU
// clock), readback (from the first dispatch to the pairs in hand, CPU exact tests included)
// and dispatch (the part of readback spent submitting the passes and waiting for them,
// glFinish). last_stats(): what the last call did.
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
  std::chrono::nanoseconds dispatch{0};  // included in readback
};

// Counts of the last detect/detect_all call.
struct CollisionStats {
  int submissions = 0;      // 0 (every list answered from its last computation) or 1
  int lists = 0;            // lists recomputed on the GPU (the asked ones and those riding along)
  std::uint64_t slots = 0;  // triangles of those lists
  std::uint64_t entries = 0, candidates = 0;  // (triangle, cell) entries; box pairs tested
  std::uint64_t undecided = 0;  // candidates the float test left to the CPU's exact test
  int cpu_lists = 0;            // lists run on the CPU reference (non-finite positions)
};

class CollisionDetector {
 public:
  explicit CollisionDetector(const Context& context);
  ~CollisionDetector();
  CollisionDetector(const CollisionDetector&) = delete;
  CollisionDetector& operator=(const CollisionDetector&) = delete;

  void detect(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
              std::span<const std::uint32_t> triangles, std::vector<deform::TrianglePair>& pairs);
  void detect_all(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                  std::span<const std::span<const std::uint32_t>> lists,
                  std::span<std::vector<deform::TrianglePair>> pairs);
  const CollisionTimings& last_timings() const { return timings_; }
  const CollisionStats& last_stats() const { return stats_; }

 private:
  struct List;
  struct Buffers;

  // The cached list equal to `triangles` under `indices`, learnt (uploaded) when new.
  std::size_t find_or_learn(std::span<const std::uint32_t> indices,
                            std::span<const std::uint32_t> triangles);
  // Compares the list's corners with `positions`, keeps them, sets its cell size. Returns true
  // when they changed (or it was never computed).
  bool refresh(List& list, std::span<const glm::vec3> positions);
  void queue_if_stale(std::size_t list, std::span<const glm::vec3> positions);
  void run_batch(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices);
  void submit(std::span<const glm::vec3> positions);
  void grow_slots(std::size_t slots);
  void allocate(int binding, std::size_t bytes, const void* data);

  const GlFunctions& gl_;
  std::vector<std::unique_ptr<ShaderProgram>> passes_;
  std::unique_ptr<Buffers> buffers_;
  std::vector<List> lists_;
  std::vector<std::uint32_t> slot_list_;  // per slot, its list
  std::size_t slots_used_ = 0;
  std::uint64_t cache_epoch_ = 0;        // counts the times the cache started over
  std::vector<std::size_t> asked_;        // per list of the call, its cached list
  std::vector<std::size_t> batch_;        // lists of the next submission
  std::vector<glm::uvec4> batch_table_;   // their (first slot, list, first active, 1/cell)
  std::vector<std::uint32_t> readback_;   // header and pairs
  std::size_t readback_window_ = 1024;    // pairs read with the header
  deform::SelfIntersectionDetector cpu_;
  std::chrono::steady_clock::time_point first_dispatch_;
  CollisionTimings timings_;
  CollisionStats stats_;
};

}  // namespace sweepd::gpu
