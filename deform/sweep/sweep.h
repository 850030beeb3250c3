// Sweep: the control sweep surface of a moving ellipse (paper §3.1–3.2),
//   S(θ, t) = R(t) (o_x(t) + a(t) cos θ, o_y(t) + b(t) sin θ, 0)^T + C(t),   t in [0, 1],
// i.e. an ellipse centred at C̃(t) = C(t) + R(t) (o_x(t), o_y(t), 0) (KeyEllipse::offset),
// built from n+1 >= 2 key ellipses:
// - t_i: chord-length parameters of the key centres at construction, normalised to [0, 1].
//   They stay fixed afterwards (t is a material coordinate: vertex bindings (t_V, θ_V) remain
//   valid while the keys move).
// - C(t): C2 cubic spline through the centres, knots t_i (InterpolatingCubicSpline; not-a-knot
//   ends by default, a straight segment for 2 keys).
// - R(t): rotation of the orientation curve Q(t) through the key orientations
//   (OrientationCurve: the paper's normalised piecewise-linear unit quaternions by default, or
//   the C2 cumulative B-spline); N(t) is its third column.
// - a(t), b(t): quadratic B-spline functions interpolating the key half-axes; their control
//   values α_i, β_i (one per key) are exposed for the volume correction of §4.4.
// - o(t) = (o_x(t), o_y(t)): the keys' in-plane offsets, interpolated like a and b (the same
//   quadratic B-spline basis). C(t) passes through the key centres (the joints), so spans far
//   from a bent joint stay rigid, while the ellipses sit on the sections beside the joints.
// Per frame, set_key_frames() re-solves C and Q from new key centres/orientations without
// allocating; a, b and o are kept (the paper changes a and b only through volume correction or
// edits; o is in the keys' own frames, so it turns with them).
// Evaluation at t outside [0, 1] extends the end pieces of every curve.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <span>
#include <vector>

#include "deform/sweep/interpolating_splines.h"
#include "deform/sweep/key_ellipse.h"
#include "deform/sweep/orientation_curve.h"

namespace sweepd::deform {

// Everything a vertex bound at parameter t needs: V = C̃ + R ((a cos θ, b sin θ, 0) + d).
struct SweepFrame {
  glm::vec3 centre{0.0f};    // C̃(t), the ellipse's centre
  glm::mat3 rotation{1.0f};  // R(t); its third column is N(t)
  float a = 0.0f, b = 0.0f;  // a(t), b(t)
};

class Sweep {
 public:
  // keys: n+1 >= 2 key ellipses in sweep order. Throws std::invalid_argument (with the reason)
  // for fewer than 2 keys, coincident consecutive centres, non-positive or non-finite half-axes.
  explicit Sweep(std::span<const KeyEllipse> keys, SplineEnds ends = SplineEnds::kNotAKnot,
                 OrientationCurveKind orientation = OrientationCurveKind::kLinear);

  // New centres and orientations (same count as at construction); a and b are ignored.
  // Allocation-free. Throws std::invalid_argument on a count mismatch.
  void set_key_frames(std::span<const KeyEllipse> keys);
  // Re-interpolates a(t), b(t) through the keys' half-axes (resets the volume correction) and
  // o(t) through their offsets.
  // Allocation-free. Throws std::invalid_argument on a count mismatch.
  void set_key_half_axes(std::span<const KeyEllipse> keys);

  int key_count() const { return static_cast<int>(parameters_.size()); }
  std::span<const double> parameters() const { return parameters_; }  // t_i, n+1 values

  glm::vec3 centre(float t) const { return glm::vec3(centre_.position(t)); }               // C(t)
  glm::quat orientation(float t) const { return glm::quat(orientation_.unit(t)); }         // unit
  glm::mat3 rotation(float t) const { return glm::mat3(orientation_.rotation(t)); }        // R(t)
  glm::vec3 normal(float t) const { return rotation(t)[2]; }                               // N(t)
  float a(float t) const { return static_cast<float>(a_.value(t)); }
  float b(float t) const { return static_cast<float>(b_.value(t)); }
  glm::vec2 offset(float t) const;          // o(t)
  glm::vec3 ellipse_centre(float t) const;  // C̃(t) = C(t) + R(t) (o(t), 0)
  // C̃'(t) = C'(t) + R'(t) (o, 0) + R(t) (o', 0), in double precision (the volume integral).
  glm::dvec3 ellipse_centre_derivative(double t) const;
  // S(θ, t).
  glm::vec3 point(float theta, float t) const;
  // C̃, R, a, b at t in one evaluation.
  SweepFrame frame(float t) const;
  // frame(t[i]) for every i into out[i]; t and out have the same size. No allocation.
  void frames(std::span<const float> t, std::span<SweepFrame> out) const;

  // Control values α_i of a(t) and β_i of b(t), one per key; writable (volume correction).
  std::span<double> alpha() { return a_.controls(); }
  std::span<double> beta() { return b_.controls(); }
  std::span<const double> alpha() const { return a_.controls(); }
  std::span<const double> beta() const { return b_.controls(); }

  // The underlying curves, in double precision (used by the volume integral).
  const InterpolatingCubicSpline& centre_curve() const { return centre_; }
  const OrientationCurve& orientation_curve() const { return orientation_; }
  const InterpolatingQuadraticSpline& a_function() const { return a_; }
  const InterpolatingQuadraticSpline& b_function() const { return b_; }
  const InterpolatingQuadraticSpline& offset_x_function() const { return offset_x_; }
  const InterpolatingQuadraticSpline& offset_y_function() const { return offset_y_; }

 private:
  std::vector<double> parameters_;
  std::vector<glm::vec3> centres_;  // scratch for set_key_frames
  std::vector<double> key_values_;  // scratch for set_key_half_axes
  InterpolatingCubicSpline centre_;
  OrientationCurve orientation_;
  InterpolatingQuadraticSpline a_, b_, offset_x_, offset_y_;
};

}  // namespace sweepd::deform
