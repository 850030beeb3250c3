// Spline interpolation for sweep surfaces (paper §3.2): the cubic centre curve C(t) through the
// key-ellipse centres and the quadratic B-spline functions a(t), b(t) through the key half-axes.
//
// Both classes split the work in two so the per-frame update is cheap and allocation-free:
// - set_parameters(t)    t: n+1 strictly increasing parameters (n >= 1). Allocates, factors the
//                        (tridiagonal) interpolation system once.
// - interpolate(values)  values: n+1 data values. Solves with the stored factors; no allocation.
// Evaluation outside [t_0, t_n] extends the first/last polynomial piece.
// Internals are double precision: the swept-volume integral needs ~1e-7 relative accuracy.
#pragma once

#include <array>
#include <glm/glm.hpp>
#include <span>
#include <vector>

namespace sweepd::deform {

// Chord-length parameters of a polyline, normalised to [0, 1]:
// t_0 = 0, t_i = t_{i-1} + |p_i - p_{i-1}| / L, t_n = 1, where L is the total length.
// points: n+1 points; params: n+1 outputs. Returns false (params untouched) when two consecutive
// points coincide or there are fewer than two points, i.e. when no strictly increasing
// parametrisation exists.
bool chord_length_parameters(std::span<const glm::vec3> points, std::span<double> params);

// End conditions of the cubic interpolant.
enum class SplineEnds {
  kNotAKnot,  // C''' continuous at t_1 and t_{n-1}; reproduces cubics; 3 points: the parabola
  kNatural,   // C''(t_0) = C''(t_n) = 0
};

// C2 cubic spline through n+1 points, knots at the data parameters. This is the cubic B-spline
// interpolant with those knots, held in second-derivative (piecewise polynomial) form.
// With 2 points it is the straight segment.
class InterpolatingCubicSpline {
 public:
  // params: n+1 strictly increasing values, n >= 1. Throws std::invalid_argument otherwise.
  void set_parameters(std::span<const double> params, SplineEnds ends = SplineEnds::kNotAKnot);
  // points: exactly parameter_count() points. Throws std::invalid_argument on a size mismatch.
  void interpolate(std::span<const glm::vec3> points);

  glm::dvec3 position(double t) const;    // C(t)
  glm::dvec3 derivative(double t) const;  // C'(t)
  int parameter_count() const { return static_cast<int>(t_.size()); }
  std::span<const double> parameters() const { return t_; }

  // C(t) as fixed weights of the data: C(t) = w[0] P_i + w[1] P_{i+1} + w[2] P''_i +
  // w[3] P''_{i+1} on span i. The weights depend on t only, so a point bound at a fixed t (a
  // vertex's t_V) is re-evaluated each frame, exactly, from points() and second_derivatives().
  struct Weights {
    int span = 0;
    std::array<double, 4> w{};
  };
  Weights weights(double t) const;
  std::span<const glm::dvec3> points() const { return points_; }
  std::span<const glm::dvec3> second_derivatives() const { return second_; }

 private:
  int span_of(double t) const;

  SplineEnds ends_ = SplineEnds::kNotAKnot;
  std::vector<double> t_;
  std::vector<glm::dvec3> points_;
  std::vector<glm::dvec3> second_;  // C''(t_i)
  // Thomas factors of the system for C''(t_1..t_{n-1}).
  std::vector<double> lower_, pivot_, upper_;
  std::vector<glm::dvec3> rhs_;
};

// Quadratic B-spline function f(t) = sum_i c_i B_i(t) with n+1 control values c_i that
// interpolates n+1 values at the sites t_i. Knot vector: t_0 (x3), the midpoints
// (t_{i-1}+t_i)/2 for i = 2..n-1, t_n (x3) — the Schoenberg–Whitney choice for even degree, so
// the system is tridiagonal and B_i peaks near t_i (control i belongs to key ellipse i).
// Reproduces linear functions exactly. With 2 sites it is the linear function (degree 1).
// The control values are public (controls()) because the volume correction of §4.4 edits them.
class InterpolatingQuadraticSpline {
 public:
  static constexpr int kMaxDegree = 2;

  // sites: n+1 strictly increasing values, n >= 1. Throws std::invalid_argument otherwise.
  void set_parameters(std::span<const double> sites);
  // values: exactly control_count() values; sets the control values. No allocation.
  void interpolate(std::span<const double> values);

  double value(double t) const;
  // The degree()+1 basis functions that may be nonzero at t: B_first .. B_{first+degree()};
  // writes them to basis[0..degree()] and returns first.
  int nonzero_basis(double t, std::array<double, kMaxDegree + 1>& basis) const;
  int degree() const { return degree_; }
  int control_count() const { return static_cast<int>(controls_.size()); }
  std::span<double> controls() { return controls_; }
  std::span<const double> controls() const { return controls_; }
  std::span<const double> knots() const { return knots_; }

 private:
  int degree_ = kMaxDegree;
  std::vector<double> knots_;
  std::vector<double> controls_;
  std::vector<double> lower_, pivot_, upper_;  // Thomas factors of the interpolation system
};

}  // namespace sweepd::deform
