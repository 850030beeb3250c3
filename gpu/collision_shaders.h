// The GLSL compute passes of gpu::CollisionDetector (gpu/collision.h): a spatial hash built by
// counting sort, the pairs per cell, and the narrow phase in float with a certified sign filter.
//
// collision_pass_source(pass) -> the whole GLSL 4.50 source of one pass (compiled once per
// detector). The buffers every pass sees (std430, binding points in CollisionBinding):
//   positions   float[3 #V]           the posed positions, uploaded once per submission
//   records     uvec4 per slot        welded corner indices and the triangle id (topology,
//                                      uploaded once per list)
//   batch       uvec4 per list        first slot, list id, first active index, 1/cell (bits)
//   output      uint header[16], then uvec2 per pair found: header[0] entries, [1] candidates,
//                                      [2] pairs found, [3] the buckets' allocation cursor,
//                                      [4..6] and [8..10] indirect dispatch sizes
//   boxes       vec4 ×2 per slot      lo (w: 1/cell), hi (w: list id, exact in float)
//   entries, sorted  uvec4 per (slot, cell): the cell's integer coordinates and the slot
//   buckets     uint ×2 per bucket    count, then the cursor (the bucket's end after scatter)
//   candidates  uvec2 per box pair    slots, the smaller triangle id first
// A found pair is (slot a, slot b) with bit 31 of a set when the float test could not decide.
#pragma once

#include <string>

namespace sweepd::gpu {

enum class CollisionPass {
  kBoxes,       // per active slot: box, cell range, entries, bucket counts
  kBuckets,     // per 16 buckets: where their entries go (one atomic per 16 buckets)
  kScatter,     // per entry: into its bucket
  kCellPairs,   // per entry: later entries of its bucket, same cell and list, boxes overlap,
                // overlap's lower corner in this cell, no shared vertex -> candidate
  kNarrowSize,  // one invocation: the narrow phase's dispatch size
  kNarrow,      // per candidate: the float test; intersecting or undecided -> output
};

enum CollisionBinding : unsigned {
  kPositionsBinding = 0,
  kRecordsBinding,
  kBatchBinding,
  kOutputBinding,
  kBoxesBinding,
  kEntriesBinding,
  kSortedBinding,
  kBucketsBinding,
  kCandidatesBinding,
};

inline constexpr unsigned kCollisionGroupSize = 64;    // invocations per workgroup
inline constexpr unsigned kBucketsPerInvocation = 16;  // of the kBuckets pass
inline constexpr unsigned kOutputHeaderWords = 16;    // uints before the pairs in `output`
inline constexpr unsigned kUndecidedBit = 0x80000000u;

std::string collision_pass_source(CollisionPass pass);

}  // namespace sweepd::gpu
