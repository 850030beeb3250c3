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

// Which cubic interpolant, and its end conditions.
enum class SplineEnds {
  kNotAKnot,  // C2 (the cubic B-spline interpolant); C''' continuous at t_1 and t_{n-1};
              // reproduces cubics; 3 points: the parabola
  kNatural,   // C2, C''(t_0) = C''(t_n) = 0
  kLocal,     // C1 piecewise cubic Hermite with Bessel (chord-length weighted) tangents, ends
              // from the parabola through the end points: a point moves only the two spans on
              // each side of it, so bending one joint leaves the rest of a limb's curve rigid
};

// Cubic spline through n+1 points, knots at the data parameters: the C2 cubic B-spline
// interpolant (kNotAKnot, kNatural) or the local C1 one (kLocal), held in piecewise polynomial
// form (end values and end second derivatives of every span). With 2 points it is the segment.
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

  // C(t) as fixed weights of the data: C(t) = w[0] P_i + w[1] P_{i+1} + w[2] S_{2i} +
  // w[3] S_{2i+1} on span i, with S = span_second_derivatives(). The weights depend on t only,
  // so a point bound at a fixed t (a vertex's t_V) is re-evaluated each frame, exactly.
  struct Weights {
    int span = 0;
    std::array<double, 4> w{};
  };
  Weights weights(double t) const;
  std::span<const glm::dvec3> points() const { return points_; }
  // C'' at the start and at the end of every span: 2n values (equal across a knot for C2).
  std::span<const glm::dvec3> span_second_derivatives() const { return span_second_; }

 private:
  int span_of(double t) const;
  void global_second_derivatives();
  void local_second_derivatives();

  SplineEnds ends_ = SplineEnds::kNotAKnot;
  std::vector<double> t_;
  std::vector<glm::dvec3> points_;
  std::vector<glm::dvec3> second_;       // C''(t_i) of the C2 kinds
  std::vector<glm::dvec3> span_second_;  // C'' at both ends of each span
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
  double derivative(double t) const;  // f'(t) (one-sided at the knots, where f' may jump)
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
