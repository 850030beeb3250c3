#include "gpu/collision.h"

#include <algorithm>
#include <stdexcept>

namespace sweepd::gpu {
namespace {

// deform/features/triangle_intersection.cpp in GLSL: keep both in step, operation for operation.
const char* const kSource = R"(#version 450 core
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Corners { vec4 corners[]; };      // 3 per slot
layout(std430, binding = 1) readonly buffer Records { uvec4 records[]; };     // welded corners, id
layout(std430, binding = 2) buffer Count { uint pair_count; };
layout(std430, binding = 3) writeonly buffer Pairs { uvec2 pairs[]; };

uniform int slot_count;
uniform int pair_capacity;

double orient3d(dvec3 a, dvec3 b, dvec3 c, dvec3 d) {
  precise dvec3 u = b - a;
  precise dvec3 v = c - a;
  precise dvec3 w = d - a;
  precise double x = u.y * v.z - u.z * v.y;
  precise double y = u.z * v.x - u.x * v.z;
  precise double z = u.x * v.y - u.y * v.x;
  precise double r = (w.x * x + w.y * y) + w.z * z;
  return r;
}

double orient2d(dvec2 a, dvec2 b, dvec2 c) {
  precise double r = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  return r;
}

bool opposite_signs(double s, double t) { return (s > 0.0 && t < 0.0) || (s < 0.0 && t > 0.0); }

bool one_side(double s, double t, double u) {
  return (s > 0.0 && t > 0.0 && u > 0.0) || (s < 0.0 && t < 0.0 && u < 0.0);
}

bool within_box(dvec2 a, dvec2 b, dvec2 p) {
  return min(a.x, b.x) <= p.x && p.x <= max(a.x, b.x) && min(a.y, b.y) <= p.y &&
         p.y <= max(a.y, b.y);
}

bool segments_intersect(dvec2 a, dvec2 b, dvec2 c, dvec2 d) {
  double d1 = orient2d(c, d, a), d2 = orient2d(c, d, b);
  double d3 = orient2d(a, b, c), d4 = orient2d(a, b, d);
  if (opposite_signs(d1, d2) && opposite_signs(d3, d4)) return true;
  return (d1 == 0.0 && within_box(c, d, a)) || (d2 == 0.0 && within_box(c, d, b)) ||
         (d3 == 0.0 && within_box(a, b, c)) || (d4 == 0.0 && within_box(a, b, d));
}

bool point_in_triangle(dvec2 t0, dvec2 t1, dvec2 t2, dvec2 p) {
  double s0 = orient2d(t0, t1, p), s1 = orient2d(t1, t2, p), s2 = orient2d(t2, t0, p);
  bool negative = s0 < 0.0 || s1 < 0.0 || s2 < 0.0;
  bool positive = s0 > 0.0 || s1 > 0.0 || s2 > 0.0;
  return !(negative && positive);
}

dvec3 a[3], b[3];  // the two triangles of the current test (per invocation)

bool coplanar_triangles_intersect(dvec3 n) {
  dvec3 m = abs(n);
  int drop = (m.x >= m.y && m.x >= m.z) ? 0 : (m.y >= m.z ? 1 : 2);
  int u = drop == 0 ? 1 : 0, v = drop == 2 ? 1 : 2;
  dvec2 p[3], q[3];
  for (int i = 0; i < 3; ++i) {
    p[i] = dvec2(a[i][u], a[i][v]);
    q[i] = dvec2(b[i][u], b[i][v]);
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (segments_intersect(p[i], p[(i + 1) % 3], q[j], q[(j + 1) % 3])) return true;
  return point_in_triangle(p[0], p[1], p[2], q[0]) || point_in_triangle(q[0], q[1], q[2], p[0]);
}

bool intervals_overlap(dvec3 p1, dvec3 q1, dvec3 r1, dvec3 p2, dvec3 q2, dvec3 r2) {
  if (orient3d(q1, p2, p1, q2) > 0.0) return false;
  if (orient3d(p1, p2, r1, r2) > 0.0) return false;
  return true;
}

bool check_against_b(dvec3 p1, dvec3 q1, dvec3 r1, dvec3 p2, dvec3 q2, dvec3 r2, double dp2,
                     double dq2, double dr2, dvec3 n1) {
  if (dp2 > 0.0) {
    if (dq2 > 0.0) return intervals_overlap(p1, r1, q1, r2, p2, q2);
    if (dr2 > 0.0) return intervals_overlap(p1, r1, q1, q2, r2, p2);
    return intervals_overlap(p1, q1, r1, p2, q2, r2);
  }
  if (dp2 < 0.0) {
    if (dq2 < 0.0) return intervals_overlap(p1, q1, r1, r2, p2, q2);
    if (dr2 < 0.0) return intervals_overlap(p1, q1, r1, q2, r2, p2);
    return intervals_overlap(p1, r1, q1, p2, q2, r2);
  }
  if (dq2 < 0.0) {
    if (dr2 >= 0.0) return intervals_overlap(p1, r1, q1, q2, r2, p2);
    return intervals_overlap(p1, q1, r1, p2, q2, r2);
  }
  if (dq2 > 0.0) {
    if (dr2 > 0.0) return intervals_overlap(p1, r1, q1, p2, q2, r2);
    return intervals_overlap(p1, q1, r1, q2, r2, p2);
  }
  if (dr2 > 0.0) return intervals_overlap(p1, q1, r1, r2, p2, q2);
  if (dr2 < 0.0) return intervals_overlap(p1, r1, q1, r2, p2, q2);
  return coplanar_triangles_intersect(n1);
}

dvec3 normal_of(dvec3 t0, dvec3 t1, dvec3 t2) {
  precise dvec3 u = t0 - t2;
  precise dvec3 v = t1 - t2;
  precise dvec3 n = dvec3(u.y * v.z - u.z * v.y, u.z * v.x - u.x * v.z, u.x * v.y - u.y * v.x);
  return n;
}

bool triangles_intersect() {
  dvec3 n1 = normal_of(a[0], a[1], a[2]), n2 = normal_of(b[0], b[1], b[2]);
  if (n1 == dvec3(0.0) || n2 == dvec3(0.0)) return false;
  double dp1 = orient3d(b[2], b[0], b[1], a[0]);
  double dq1 = orient3d(b[2], b[0], b[1], a[1]);
  double dr1 = orient3d(b[2], b[0], b[1], a[2]);
  if (one_side(dp1, dq1, dr1)) return false;
  double dp2 = orient3d(a[2], a[0], a[1], b[0]);
  double dq2 = orient3d(a[2], a[0], a[1], b[1]);
  double dr2 = orient3d(a[2], a[0], a[1], b[2]);
  if (one_side(dp2, dq2, dr2)) return false;
  dvec3 p1 = a[0], q1 = a[1], r1 = a[2], p2 = b[0], q2 = b[1], r2 = b[2];
  if (dp1 > 0.0) {
    if (dq1 > 0.0) return check_against_b(r1, p1, q1, p2, r2, q2, dp2, dr2, dq2, n1);
    if (dr1 > 0.0) return check_against_b(q1, r1, p1, p2, r2, q2, dp2, dr2, dq2, n1);
    return check_against_b(p1, q1, r1, p2, q2, r2, dp2, dq2, dr2, n1);
  }
  if (dp1 < 0.0) {
    if (dq1 < 0.0) return check_against_b(r1, p1, q1, p2, q2, r2, dp2, dq2, dr2, n1);
    if (dr1 < 0.0) return check_against_b(q1, r1, p1, p2, q2, r2, dp2, dq2, dr2, n1);
    return check_against_b(p1, q1, r1, p2, r2, q2, dp2, dr2, dq2, n1);
  }
  if (dq1 < 0.0) {
    if (dr1 >= 0.0) return check_against_b(q1, r1, p1, p2, r2, q2, dp2, dr2, dq2, n1);
    return check_against_b(p1, q1, r1, p2, q2, r2, dp2, dq2, dr2, n1);
  }
  if (dq1 > 0.0) {
    if (dr1 > 0.0) return check_against_b(p1, q1, r1, p2, r2, q2, dp2, dr2, dq2, n1);
    return check_against_b(q1, r1, p1, p2, q2, r2, dp2, dq2, dr2, n1);
  }
  if (dr1 > 0.0) return check_against_b(r1, p1, q1, p2, q2, r2, dp2, dq2, dr2, n1);
  if (dr1 < 0.0) return check_against_b(r1, p1, q1, p2, r2, q2, dp2, dr2, dq2, n1);
  return coplanar_triangles_intersect(n1);
}

bool share_a_vertex(uvec4 s, uvec4 t) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (s[i] == t[j]) return true;
  return false;
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(slot_count)) return;
  vec3 s0 = corners[3 * i].xyz, s1 = corners[3 * i + 1].xyz, s2 = corners[3 * i + 2].xyz;
  vec3 lo = min(s0, min(s1, s2)), hi = max(s0, max(s1, s2));
  uvec4 own = records[i];
  for (uint j = i + 1; j < uint(slot_count); ++j) {
    vec3 t0 = corners[3 * j].xyz, t1 = corners[3 * j + 1].xyz, t2 = corners[3 * j + 2].xyz;
    vec3 other_lo = min(t0, min(t1, t2)), other_hi = max(t0, max(t1, t2));
    if (other_lo.x > hi.x) break;  // slots are sorted by lo.x: no later box reaches back
    if (any(greaterThan(lo, other_hi)) || any(greaterThan(other_lo, hi))) continue;
    uvec4 other = records[j];
    if (own.w == other.w || share_a_vertex(own, other)) continue;
    a[0] = dvec3(s0); a[1] = dvec3(s1); a[2] = dvec3(s2);
    b[0] = dvec3(t0); b[1] = dvec3(t1); b[2] = dvec3(t2);
    if (!triangles_intersect()) continue;
    uint slot = atomicAdd(pair_count, 1u);
    if (slot < uint(pair_capacity)) pairs[slot] = uvec2(min(own.w, other.w), max(own.w, other.w));
  }
}
)";

}  // namespace

CollisionDetector::CollisionDetector(const Context& context)
    : gl_(context.gl()), program_(context.gl(), "collision", kSource) {
  gl_.GenBuffers(4, buffers_);
  throw_on_gl_error(gl_, "collision buffers");
}

CollisionDetector::~CollisionDetector() { gl_.DeleteBuffers(4, buffers_); }

void CollisionDetector::detect(std::span<const glm::vec3> positions,
                               std::span<const std::uint32_t> indices,
                               std::span<const std::uint32_t> triangles,
                               std::vector<deform::TrianglePair>& pairs) {
  using Clock = std::chrono::steady_clock;
  pairs.clear();
  timings_ = {};
  if (triangles.size() < 2) return;
  const Clock::time_point started = Clock::now();
  const std::size_t count = triangles.size();
  corners_.resize(3 * count);
  records_.resize(count);
  // Sort and sweep along x: slots ordered by their boxes' lower x, so each invocation stops at
  // the first later box that starts past its own.
  order_.resize(count);
  for (std::size_t s = 0; s < count; ++s) {
    const std::uint32_t t = triangles[s];
    const float x0 = positions[indices[3 * t]].x, x1 = positions[indices[3 * t + 1]].x,
                x2 = positions[indices[3 * t + 2]].x;
    order_[s] = {std::min(x0, std::min(x1, x2)), t};
  }
  std::sort(order_.begin(), order_.end());
  for (std::size_t s = 0; s < count; ++s) {
    const std::uint32_t t = order_[s].second;
    for (int k = 0; k < 3; ++k) corners_[3 * s + k] = glm::vec4(positions[indices[3 * t + k]], 0);
    records_[s] = glm::uvec4(indices[3 * t], indices[3 * t + 1], indices[3 * t + 2], t);
  }
  auto upload = [&](int slot, std::size_t bytes, const void* data) {
    gl_.BindBuffer(GL_SHADER_STORAGE_BUFFER, buffers_[slot]);
    gl_.BufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(bytes), data, GL_STREAM_DRAW);
    gl_.BindBufferBase(GL_SHADER_STORAGE_BUFFER, slot, buffers_[slot]);
  };
  upload(0, corners_.size() * sizeof(glm::vec4), corners_.data());
  upload(1, records_.size() * sizeof(glm::uvec4), records_.data());
  pair_capacity_ = std::max(pair_capacity_, std::max<std::size_t>(4096, 4 * count));

  const Clock::time_point uploaded = Clock::now();
  program_.use();
  gl_.Uniform1i(program_.uniform("slot_count"), static_cast<GLint>(count));
  for (;;) {
    const GLuint zero = 0;
    upload(2, sizeof(GLuint), &zero);
    upload(3, pair_capacity_ * sizeof(glm::uvec2), nullptr);
    gl_.Uniform1i(program_.uniform("pair_capacity"), static_cast<GLint>(pair_capacity_));
    gl_.DispatchCompute(static_cast<GLuint>((count + 63) / 64), 1, 1);
    gl_.MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    GLuint found = 0;
    gl_.BindBuffer(GL_SHADER_STORAGE_BUFFER, buffers_[2]);
    gl_.GetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof(GLuint), &found);
    throw_on_gl_error(gl_, "collision dispatch");
    if (found > pair_capacity_) {  // the buffer was too small: grow and run again
      pair_capacity_ = 2 * static_cast<std::size_t>(found);
      continue;
    }
    found_.resize(found);
    if (found > 0) {
      gl_.BindBuffer(GL_SHADER_STORAGE_BUFFER, buffers_[3]);
      gl_.GetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0,
                           static_cast<GLsizeiptr>(found * sizeof(glm::uvec2)), found_.data());
    }
    break;
  }
  const Clock::time_point read = Clock::now();
  timings_ = {uploaded - started, read - uploaded};
  pairs.reserve(found_.size());
  for (const glm::uvec2& p : found_) pairs.push_back({p.x, p.y});
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
}

}  // namespace sweepd::gpu
