#include "gpu/collision_shaders.h"

#include <initializer_list>

namespace sweepd::gpu {
namespace {

// Each pass declares only the buffers it uses: GL promises 8 storage blocks per compute shader.
const char* const kBlocks[] = {
    "layout(std430, binding = 0) readonly buffer Positions { float positions[]; };\n",
    "layout(std430, binding = 1) readonly buffer Records { uvec4 records[]; };\n",
    "layout(std430, binding = 2) readonly buffer Batch { uvec4 batch[]; };\n",
    "layout(std430, binding = 3) buffer Output { uint header[16]; uvec2 found[]; };\n",
    "layout(std430, binding = 4) buffer Boxes { vec4 boxes[]; };\n",
    "layout(std430, binding = 5) buffer Entries { uvec4 entries[]; };\n",
    "layout(std430, binding = 6) buffer Sorted { uvec4 sorted[]; };\n",
    "layout(std430, binding = 7) buffer Buckets { uint buckets[]; };\n",
    "layout(std430, binding = 8) buffer Candidates { uvec2 candidates[]; };\n",
};

const char* const kCommon = R"(
uniform uint active_count;     // slots of this submission
uniform uint batch_count;      // lists of this submission
uniform uint bucket_mask;      // buckets - 1 (a power of two)
uniform uint entry_capacity;
uniform uint candidate_capacity;
uniform uint output_capacity;

// Cell coordinates of a point: floor(p / cell) through a correctly rounded product (monotone in
// p, unlike GLSL's division), clamped (also monotone) so the integer conversion is defined. A
// point inside a box lies in a cell of the box's cell range, whatever the rounding.
ivec3 cell_of(vec3 p, float inverse_cell) {
  precise vec3 scaled = p * inverse_cell;
  return ivec3(clamp(floor(scaled), vec3(-1048576.0), vec3(1048575.0)));
}

uint bucket_of(uvec3 cell, uint list) {
  return ((cell.x * 73856093u) ^ (cell.y * 19349663u) ^ (cell.z * 83492791u) ^
          (list * 2654435761u)) & bucket_mask;
}

uint stored_entries() { return min(header[0], entry_capacity); }

// Invocations of the dispatch: the per-item passes loop over their items in strides of it (a
// dispatch holds at most 65,535 workgroups along x).
uint stride() { return gl_NumWorkGroups.x * gl_WorkGroupSize.x; }
)";

const char* const kBoxesPass = R"(
vec3 corner(uint v) { return vec3(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]); }

void box(uint i) {
  uint first = 0, last = batch_count - 1;  // the list: the last one starting at or before i
  while (first < last) {
    uint middle = (first + last + 1) / 2;
    if (batch[middle].z <= i) first = middle; else last = middle - 1;
  }
  uvec4 list = batch[first];
  uint slot = list.x + (i - list.z);
  uvec4 record = records[slot];
  vec3 p = corner(record.x), q = corner(record.y), r = corner(record.z);
  vec3 lo = min(p, min(q, r)), hi = max(p, max(q, r));
  float inverse_cell = uintBitsToFloat(list.w);
  boxes[2 * slot] = vec4(lo, inverse_cell);
  boxes[2 * slot + 1] = vec4(hi, float(list.y));  // list ids are small: exact in float
  ivec3 c0 = cell_of(lo, inverse_cell), c1 = cell_of(hi, inverse_cell);
  uvec3 n = uvec3(c1 - c0) + 1u;
  uint base = atomicAdd(header[0], n.x * n.y * n.z);
  for (int x = c0.x; x <= c1.x; ++x)
    for (int y = c0.y; y <= c1.y; ++y)
      for (int z = c0.z; z <= c1.z; ++z, ++base) {
        if (base >= entry_capacity) return;  // the caller grows the buffer and runs again
        uvec3 cell = uvec3(ivec3(x, y, z));
        entries[base] = uvec4(cell, slot);
        atomicAdd(buckets[2 * bucket_of(cell, list.y)], 1u);
      }
}

void main() {
  for (uint i = gl_GlobalInvocationID.x; i < active_count; i += stride()) box(i);
}
)";

// Each invocation owns kBucketsPerInvocation consecutive buckets: their counts summed, one
// atomic for their place, then their starts (no shared memory, no barriers: llvmpipe runs a
// barrier by switching between every invocation of the group).
const char* const kBucketsPass = R"(
const uint kBucketsPerInvocation = 16u;

void main() {
  uint first = gl_GlobalInvocationID.x * kBucketsPerInvocation;
  if (first <= bucket_mask) {
    uint sum = 0u;
    for (uint b = first; b < first + kBucketsPerInvocation; ++b) sum += buckets[2 * b];
    uint start = atomicAdd(header[3], sum);
    for (uint b = first; b < first + kBucketsPerInvocation; ++b) {
      uint count = buckets[2 * b];
      buckets[2 * b] = 0u;  // zero again for the next submission
      buckets[2 * b + 1] = start;
      start += count;
    }
  }
  if (gl_GlobalInvocationID.x == 0u) {  // the scatter and cell passes' size, from the entries
    uint n = header[0] <= entry_capacity ? header[0] : 0u;
    header[4] = min((n + 63u) / 64u, 65535u);  // kCollisionGroupSize
    header[5] = 1u;
    header[6] = 1u;
  }
}
)";

const char* const kScatterPass = R"(
void main() {
  for (uint e = gl_GlobalInvocationID.x; e < stored_entries(); e += stride()) {
    uvec4 entry = entries[e];
    uint list = uint(boxes[2 * entry.w + 1].w);
    uint at = atomicAdd(buckets[2 * bucket_of(entry.xyz, list) + 1], 1u);
    sorted[at] = entry;
  }
}
)";

const char* const kCellPairsPass = R"(
bool share_a_vertex(uvec4 s, uvec4 t) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (s[i] == t[j]) return true;
  return false;
}

void cell_pairs(uint p) {
  uvec4 entry = sorted[p];
  uint s = entry.w;
  vec4 s_lo = boxes[2 * s], s_hi = boxes[2 * s + 1];
  uint list = uint(s_hi.w);
  uint end = buckets[2 * bucket_of(entry.xyz, list) + 1];
  uvec4 s_record = records[s];
  for (uint q = p + 1u; q < end; ++q) {
    uvec4 other = sorted[q];
    if (other.xyz != entry.xyz) continue;  // another cell in the same bucket
    uint t = other.w;
    vec4 t_lo = boxes[2 * t], t_hi = boxes[2 * t + 1];
    if (uint(t_hi.w) != list) continue;
    if (any(greaterThan(s_lo.xyz, t_hi.xyz)) || any(greaterThan(t_lo.xyz, s_hi.xyz))) continue;
    // Each box pair once: in the cell of its overlap's lower corner (the CPU's rule).
    if (uvec3(cell_of(max(s_lo.xyz, t_lo.xyz), s_lo.w)) != entry.xyz) continue;
    uvec4 t_record = records[t];
    if (share_a_vertex(s_record, t_record)) continue;
    uint k = atomicAdd(header[1], 1u);
    if (k < candidate_capacity)
      candidates[k] = s_record.w < t_record.w ? uvec2(s, t) : uvec2(t, s);
  }
}

void main() {
  for (uint p = gl_GlobalInvocationID.x; p < stored_entries(); p += stride()) cell_pairs(p);
}
)";

const char* const kNarrowSizePass = R"(
void main() {
  uint n = (header[0] <= entry_capacity && header[1] <= candidate_capacity) ? header[1] : 0u;
  header[8] = min((n + 63u) / 64u, 65535u);
  header[9] = 1u;
  header[10] = 1u;
}
)";

// Guigue–Devillers as deform/features/triangle_intersection.cpp runs it, on the same
// determinants with the same arguments in the same order, each evaluated in float with
// Shewchuk's error bound: a sign is certain when |det| > 2^-21 × permanent (+ an absolute
// 1e-30 for products flushed to zero); the CPU's double determinant then has that same sign
// (gpu/collision.h derives it). Any sign the test needs and cannot certify makes the pair
// undecided; the CPU then runs the exact test on it.
const char* const kNarrowPass = R"(
vec3 corner(uint v) { return vec3(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]); }

const float kRelativeBound = 4.76837158203125e-7;  // 2^-21 = 8 × float's unit roundoff
const float kAbsoluteBound = 1e-30;

// +1 or -1 when the sign of dot(d - a, cross(b - a, c - a)) is certain, 0 when it is not.
int orient3d_sign(vec3 a, vec3 b, vec3 c, vec3 d) {
  precise vec3 u = b - a;
  precise vec3 v = c - a;
  precise vec3 w = d - a;
  precise float x1 = u.y * v.z, x2 = u.z * v.y;
  precise float y1 = u.z * v.x, y2 = u.x * v.z;
  precise float z1 = u.x * v.y, z2 = u.y * v.x;
  precise float det = (w.x * (x1 - x2) + w.y * (y1 - y2)) + w.z * (z1 - z2);
  precise float permanent = ((abs(x1) + abs(x2)) * abs(w.x) + (abs(y1) + abs(y2)) * abs(w.y)) +
                            (abs(z1) + abs(z2)) * abs(w.z);
  precise float bound = kRelativeBound * permanent + kAbsoluteBound;
  if (det > bound) return 1;
  if (-det > bound) return -1;
  return 0;  // also NaN and infinities
}

const int kNo = 0, kYes = 1, kUndecided = 2;

int intervals_overlap(vec3 p1, vec3 q1, vec3 r1, vec3 p2, vec3 q2, vec3 r2) {
  int first = orient3d_sign(q1, p2, p1, q2);
  if (first > 0) return kNo;
  int second = orient3d_sign(p1, p2, r1, r2);
  if (second > 0) return kNo;
  return (first == 0 || second == 0) ? kUndecided : kYes;
}

// The CPU's branches; its zero branches cannot be reached (every sign here is certain).
int check_against_b(vec3 p1, vec3 q1, vec3 r1, vec3 p2, vec3 q2, vec3 r2, int dp2, int dq2,
                    int dr2) {
  if (dp2 > 0) {
    if (dq2 > 0) return intervals_overlap(p1, r1, q1, r2, p2, q2);
    if (dr2 > 0) return intervals_overlap(p1, r1, q1, q2, r2, p2);
    return intervals_overlap(p1, q1, r1, p2, q2, r2);
  }
  // dp2 < 0
  if (dq2 < 0) return intervals_overlap(p1, q1, r1, r2, p2, q2);
  if (dr2 < 0) return intervals_overlap(p1, q1, r1, q2, r2, p2);
  return intervals_overlap(p1, r1, q1, p2, q2, r2);
}

bool one_side(int s, int t, int u) { return (s > 0 && t > 0 && u > 0) || (s < 0 && t < 0 && u < 0); }

int triangles_intersect(vec3 p1, vec3 q1, vec3 r1, vec3 p2, vec3 q2, vec3 r2) {
  int dp1 = orient3d_sign(r2, p2, q2, p1);
  int dq1 = orient3d_sign(r2, p2, q2, q1);
  int dr1 = orient3d_sign(r2, p2, q2, r1);
  // Certainly all on one side: the CPU says no, by this test or by a degenerate normal first.
  if (one_side(dp1, dq1, dr1)) return kNo;
  int dp2 = orient3d_sign(r1, p1, q1, p2);
  int dq2 = orient3d_sign(r1, p1, q1, q2);
  int dr2 = orient3d_sign(r1, p1, q1, r2);
  if (one_side(dp2, dq2, dr2)) return kNo;
  // Certain nonzero signs also prove both normals nonzero in the CPU's doubles.
  if (dp1 == 0 || dq1 == 0 || dr1 == 0 || dp2 == 0 || dq2 == 0 || dr2 == 0) return kUndecided;
  if (dp1 > 0) {
    if (dq1 > 0) return check_against_b(r1, p1, q1, p2, r2, q2, dp2, dr2, dq2);
    if (dr1 > 0) return check_against_b(q1, r1, p1, p2, r2, q2, dp2, dr2, dq2);
    return check_against_b(p1, q1, r1, p2, q2, r2, dp2, dq2, dr2);
  }
  // dp1 < 0
  if (dq1 < 0) return check_against_b(r1, p1, q1, p2, q2, r2, dp2, dq2, dr2);
  if (dr1 < 0) return check_against_b(q1, r1, p1, p2, q2, r2, dp2, dq2, dr2);
  return check_against_b(p1, q1, r1, p2, r2, q2, dp2, dr2, dq2);
}

void narrow(uint k) {
  uvec2 pair = candidates[k];
  uvec4 a = records[pair.x], b = records[pair.y];
  int result = triangles_intersect(corner(a.x), corner(a.y), corner(a.z), corner(b.x),
                                   corner(b.y), corner(b.z));
  if (result == kNo) return;
  uint at = atomicAdd(header[2], 1u);
  if (at < output_capacity)
    found[at] = uvec2(pair.x | (result == kUndecided ? 0x80000000u : 0u), pair.y);
}

void main() {
  uint n = min(header[1], candidate_capacity);
  for (uint k = gl_GlobalInvocationID.x; k < n; k += stride()) narrow(k);
}
)";

std::string compose(unsigned group_size, std::initializer_list<CollisionBinding> blocks,
                    const char* body) {
  std::string source = "#version 450 core\nlayout(local_size_x = " + std::to_string(group_size) +
                       ") in;\n";
  for (const CollisionBinding block : blocks) source += kBlocks[block];
  return source + kCommon + body;
}

}  // namespace

std::string collision_pass_source(CollisionPass pass) {
  switch (pass) {
    case CollisionPass::kBoxes:
      return compose(kCollisionGroupSize,
                     {kPositionsBinding, kRecordsBinding, kBatchBinding, kOutputBinding,
                      kBoxesBinding, kEntriesBinding, kBucketsBinding},
                     kBoxesPass);
    case CollisionPass::kBuckets:
      return compose(kCollisionGroupSize, {kOutputBinding, kBucketsBinding}, kBucketsPass);
    case CollisionPass::kScatter:
      return compose(kCollisionGroupSize,
                     {kOutputBinding, kBoxesBinding, kEntriesBinding, kSortedBinding,
                      kBucketsBinding},
                     kScatterPass);
    case CollisionPass::kCellPairs:
      return compose(kCollisionGroupSize,
                     {kRecordsBinding, kOutputBinding, kBoxesBinding, kSortedBinding,
                      kBucketsBinding, kCandidatesBinding},
                     kCellPairsPass);
    case CollisionPass::kNarrowSize:
      return compose(1, {kOutputBinding}, kNarrowSizePass);
    case CollisionPass::kNarrow:
      return compose(kCollisionGroupSize,
                     {kPositionsBinding, kRecordsBinding, kOutputBinding, kCandidatesBinding},
                     kNarrowPass);
  }
  return {};
}

}  // namespace sweepd::gpu
