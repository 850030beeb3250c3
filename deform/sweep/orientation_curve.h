// OrientationCurve: the orientation curve Q(t) of a sweep (paper §3.2) through n+1 unit
// quaternions q_i at parameters t_i, in one of two kinds:
// - kLinear (the paper): piecewise-linear interpolation,
//     Q(t) = ((t_{i+1} - t) q_i + (t - t_i) q_{i+1}) / (t_{i+1} - t_i),   t_i <= t <= t_{i+1},
//   normalised to give the rotation R(t). C0: the turning rate jumps at every key.
// - kSmooth (beyond the paper): the cumulative B-spline of Kim, Kim and Shin (1995) on unit
//   quaternions with the keys as control points,
//     Q(t) = q_0 Π_{i=1..n} exp(ω_i B̃_i(t)),   ω_i = log(q_{i-1}^{-1} q_i),
//   B̃_i = Σ_{j>=i} B_j the cumulative basis of the cubic B-spline (degree min(3, n)) on the
//   clamped knots t_0 (×4), (t_j + t_{j+1} + t_{j+2}) / 3 for j = 1..n-3, t_n (×4): C2, on the
//   unit sphere, through q_0 and q_n and near the inner keys (control i's Greville point is near
//   t_i; a straight run of equal keys is reproduced), with Q' in closed form.
// Both are made sign-continuous first (q_{i+1} is negated when <q_i, q_{i+1}> < 0, so each piece
// takes the short way).
// Inputs: n+1 parameters and the kind (set once, allocates), n+1 unit quaternions per frame
// (set_keys or set_key/finish_keys: no allocation). Outside [t_0, t_n] the end pieces are
// extended (as polynomials in t inside the linear blend or the exponentials).
#pragma once

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <span>
#include <vector>

namespace sweepd::deform {

enum class OrientationCurveKind : std::int32_t {
  kLinear = 0,  // the paper's piecewise-linear unit quaternions (C0)
  kSmooth = 1,  // the cumulative cubic B-spline on unit quaternions (C2)
};

class OrientationCurve {
 public:
  // params: n+1 strictly increasing values, n >= 1. Throws std::invalid_argument otherwise.
  void set_parameters(std::span<const double> params,
                      OrientationCurveKind kind = OrientationCurveKind::kLinear);
  // keys: exactly parameter_count() quaternions (normalised here). Throws on a size mismatch.
  void set_keys(std::span<const glm::quat> keys);
  // The same for quaternions that are not contiguous (e.g. inside KeyEllipse records): set each
  // with set_key, then call finish_keys once. i must be < parameter_count().
  void set_key(int i, const glm::quat& q) { keys_[i] = glm::normalize(glm::dquat(q)); }
  void finish_keys();  // applies the sign continuity to keys set by set_key (and the ω_i)

  glm::dquat unnormalised(double t) const;  // Q(t): unit for kSmooth
  glm::dquat derivative(double t) const;    // Q'(t): constant on each piece for kLinear
  glm::dquat unit(double t) const;          // Q(t) / |Q(t)|
  glm::dmat3 rotation(double t) const;      // R(t)
  int parameter_count() const { return static_cast<int>(t_.size()); }
  OrientationCurveKind kind() const { return kind_; }
  // The key quaternions after the sign flips: <keys[i], keys[i+1]> >= 0.
  std::span<const glm::dquat> keys() const { return keys_; }
  // Where the curve's pieces meet inside (t_0, t_n): the keys' inner parameters (kLinear) or the
  // inner knots (kSmooth). Quadrature splits there.
  std::span<const double> breakpoints() const { return breakpoints_; }

 private:
  static constexpr int kMaxDegree = 3;
  int piece(double t) const;  // i with t_i <= t < t_{i+1}, clamped to the end pieces
  // kSmooth: the knot span m (degree_ <= m <= n) holding t, the cumulative basis B̃_{m-d+r}(t) and
  // its derivative for r = 1..d in cumulative[r], slope[r].
  int cumulative_basis(double t, std::array<double, kMaxDegree + 1>& cumulative,
                       std::array<double, kMaxDegree + 1>& slope) const;
  glm::dquat smooth_value(double t, glm::dquat* derivative) const;

  OrientationCurveKind kind_ = OrientationCurveKind::kLinear;
  int degree_ = 1;
  std::vector<double> t_;
  std::vector<glm::dquat> keys_;
  std::vector<double> knots_;         // kSmooth: clamped knot vector, n + degree_ + 2 values
  std::vector<glm::dvec3> log_turn_;  // kSmooth: ω_i (the vector part), ω_0 unused
  std::vector<double> breakpoints_;
};

}  // namespace sweepd::deform
