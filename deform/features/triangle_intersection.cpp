#include "deform/features/triangle_intersection.h"

namespace sweepd::deform {
namespace {

using glm::dvec2;
using glm::dvec3;

// Sign of the volume spanned by (b - a, c - a, d - a) in the form Guigue–Devillers use:
// dot(d - a, cross(b - a, c - a)). gpu/collision_shaders.cpp certifies its sign in float.
double orient3d(const dvec3& a, const dvec3& b, const dvec3& c, const dvec3& d) {
  const dvec3 u = b - a, v = c - a, w = d - a;
  const double x = u.y * v.z - u.z * v.y;
  const double y = u.z * v.x - u.x * v.z;
  const double z = u.x * v.y - u.y * v.x;
  return (w.x * x + w.y * y) + w.z * z;
}

double orient2d(const dvec2& a, const dvec2& b, const dvec2& c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

bool opposite_signs(double s, double t) { return (s > 0.0 && t < 0.0) || (s < 0.0 && t > 0.0); }

// All three strictly on one side (signs compared, not products, which could underflow).
bool one_side(double s, double t, double u) {
  return (s > 0.0 && t > 0.0 && u > 0.0) || (s < 0.0 && t < 0.0 && u < 0.0);
}

// p on the closed segment ab, given that the three are collinear.
bool within_box(const dvec2& a, const dvec2& b, const dvec2& p) {
  return glm::min(a.x, b.x) <= p.x && p.x <= glm::max(a.x, b.x) && glm::min(a.y, b.y) <= p.y &&
         p.y <= glm::max(a.y, b.y);
}

bool segments_intersect(const dvec2& a, const dvec2& b, const dvec2& c, const dvec2& d) {
  const double d1 = orient2d(c, d, a), d2 = orient2d(c, d, b);
  const double d3 = orient2d(a, b, c), d4 = orient2d(a, b, d);
  if (opposite_signs(d1, d2) && opposite_signs(d3, d4)) return true;
  return (d1 == 0.0 && within_box(c, d, a)) || (d2 == 0.0 && within_box(c, d, b)) ||
         (d3 == 0.0 && within_box(a, b, c)) || (d4 == 0.0 && within_box(a, b, d));
}

// p in the closed triangle t (either winding).
bool point_in_triangle(const dvec2* t, const dvec2& p) {
  const double s0 = orient2d(t[0], t[1], p), s1 = orient2d(t[1], t[2], p);
  const double s2 = orient2d(t[2], t[0], p);
  const bool negative = s0 < 0.0 || s1 < 0.0 || s2 < 0.0;
  const bool positive = s0 > 0.0 || s1 > 0.0 || s2 > 0.0;
  return !(negative && positive);
}

// Both triangles lie in one plane with normal n: drop n's largest axis and test in 2D.
bool coplanar_triangles_intersect(const dvec3* a, const dvec3* b, const dvec3& n) {
  const dvec3 m = glm::abs(n);
  const int drop = (m.x >= m.y && m.x >= m.z) ? 0 : (m.y >= m.z ? 1 : 2);
  const int u = drop == 0 ? 1 : 0, v = drop == 2 ? 1 : 2;
  dvec2 p[3], q[3];
  for (int i = 0; i < 3; ++i) p[i] = dvec2(a[i][u], a[i][v]), q[i] = dvec2(b[i][u], b[i][v]);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (segments_intersect(p[i], p[(i + 1) % 3], q[j], q[(j + 1) % 3])) return true;
    }
  }
  return point_in_triangle(p, q[0]) || point_in_triangle(q, p[0]);
}

// Guigue–Devillers' final interval check, with p1 alone on its side of b's plane and p2 alone
// on its side of a's plane (both on the positive side after the caller's permutations).
bool intervals_overlap(const dvec3& p1, const dvec3& q1, const dvec3& r1, const dvec3& p2,
                       const dvec3& q2, const dvec3& r2) {
  if (orient3d(q1, p2, p1, q2) > 0.0) return false;
  if (orient3d(p1, p2, r1, r2) > 0.0) return false;
  return true;
}

// Permutes b so that p2 is alone on its side of a's plane, then checks the intervals.
bool check_against_b(const dvec3& p1, const dvec3& q1, const dvec3& r1, const dvec3& p2,
                     const dvec3& q2, const dvec3& r2, double dp2, double dq2, double dr2,
                     const dvec3* a, const dvec3* b, const dvec3& n1) {
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
  return coplanar_triangles_intersect(a, b, n1);
}

dvec3 normal_of(const dvec3* t) {
  const dvec3 u = t[0] - t[2], v = t[1] - t[2];
  return dvec3(u.y * v.z - u.z * v.y, u.z * v.x - u.x * v.z, u.x * v.y - u.y * v.x);
}

}  // namespace

bool triangles_intersect(std::span<const glm::vec3, 3> ta, std::span<const glm::vec3, 3> tb) {
  const dvec3 a[3] = {dvec3(ta[0]), dvec3(ta[1]), dvec3(ta[2])};
  const dvec3 b[3] = {dvec3(tb[0]), dvec3(tb[1]), dvec3(tb[2])};
  const dvec3 n1 = normal_of(a), n2 = normal_of(b);
  if (n1 == dvec3(0.0) || n2 == dvec3(0.0)) return false;

  // Corners of a against b's plane, and of b against a's plane.
  const double dp1 = orient3d(b[2], b[0], b[1], a[0]);
  const double dq1 = orient3d(b[2], b[0], b[1], a[1]);
  const double dr1 = orient3d(b[2], b[0], b[1], a[2]);
  if (one_side(dp1, dq1, dr1)) return false;
  const double dp2 = orient3d(a[2], a[0], a[1], b[0]);
  const double dq2 = orient3d(a[2], a[0], a[1], b[1]);
  const double dr2 = orient3d(a[2], a[0], a[1], b[2]);
  if (one_side(dp2, dq2, dr2)) return false;

  const dvec3 &p1 = a[0], &q1 = a[1], &r1 = a[2], &p2 = b[0], &q2 = b[1], &r2 = b[2];
  // Rotate a so that its first corner is alone on its side of b's plane.
  if (dp1 > 0.0) {
    if (dq1 > 0.0) return check_against_b(r1, p1, q1, p2, r2, q2, dp2, dr2, dq2, a, b, n1);
    if (dr1 > 0.0) return check_against_b(q1, r1, p1, p2, r2, q2, dp2, dr2, dq2, a, b, n1);
    return check_against_b(p1, q1, r1, p2, q2, r2, dp2, dq2, dr2, a, b, n1);
  }
  if (dp1 < 0.0) {
    if (dq1 < 0.0) return check_against_b(r1, p1, q1, p2, q2, r2, dp2, dq2, dr2, a, b, n1);
    if (dr1 < 0.0) return check_against_b(q1, r1, p1, p2, q2, r2, dp2, dq2, dr2, a, b, n1);
    return check_against_b(p1, q1, r1, p2, r2, q2, dp2, dr2, dq2, a, b, n1);
  }
  if (dq1 < 0.0) {
    if (dr1 >= 0.0) return check_against_b(q1, r1, p1, p2, r2, q2, dp2, dr2, dq2, a, b, n1);
    return check_against_b(p1, q1, r1, p2, q2, r2, dp2, dq2, dr2, a, b, n1);
  }
  if (dq1 > 0.0) {
    if (dr1 > 0.0) return check_against_b(p1, q1, r1, p2, r2, q2, dp2, dr2, dq2, a, b, n1);
    return check_against_b(q1, r1, p1, p2, q2, r2, dp2, dq2, dr2, a, b, n1);
  }
  if (dr1 > 0.0) return check_against_b(r1, p1, q1, p2, q2, r2, dp2, dq2, dr2, a, b, n1);
  if (dr1 < 0.0) return check_against_b(r1, p1, q1, p2, r2, q2, dp2, dr2, dq2, a, b, n1);
  return coplanar_triangles_intersect(a, b, n1);
}

}  // namespace sweepd::deform
