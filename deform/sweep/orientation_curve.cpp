#include "deform/sweep/orientation_curve.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "deform/sweep/bspline_basis.h"

namespace sweepd::deform {
namespace {

// exp of the pure quaternion (0, v): (cos |v|, sin |v| v / |v|).
glm::dquat exp_of(const glm::dvec3& v) {
  const double angle = glm::length(v);
  const double sinc = angle < 1e-6 ? 1.0 - angle * angle / 6.0 : std::sin(angle) / angle;
  return {std::cos(angle), sinc * v.x, sinc * v.y, sinc * v.z};
}

// The vector part of log q for a unit q with q.w >= 0 (a turn of at most π).
glm::dvec3 log_of(const glm::dquat& q) {
  const glm::dvec3 v(q.x, q.y, q.z);
  const double s = glm::length(v);
  const double angle = std::atan2(s, q.w);
  return v * (s < 1e-6 ? 1.0 + s * s / 6.0 : angle / s);
}

}  // namespace

void OrientationCurve::set_parameters(std::span<const double> params, OrientationCurveKind kind) {
  if (params.size() < 2)
    throw std::invalid_argument("quaternion curve: need at least 2 parameters");
  for (std::size_t i = 0; i + 1 < params.size(); ++i)
    if (!(params[i] < params[i + 1]))
      throw std::invalid_argument("quaternion curve: parameters must be strictly increasing");
  kind_ = kind;
  t_.assign(params.begin(), params.end());
  keys_.assign(params.size(), glm::dquat(1.0, 0.0, 0.0, 0.0));
  const int n = static_cast<int>(params.size()) - 1;
  knots_.clear();
  log_turn_.assign(params.size(), glm::dvec3(0.0));
  breakpoints_.clear();
  if (kind_ == OrientationCurveKind::kLinear) {
    degree_ = 1;
    breakpoints_.assign(params.begin() + 1, params.end() - 1);
    return;
  }
  degree_ = std::min(kMaxDegree, n);
  knots_.assign(degree_ + 1, params.front());
  for (int j = 1; j <= n - degree_; ++j) {
    double sum = 0.0;
    for (int k = 0; k < degree_; ++k) sum += params[j + k];
    knots_.push_back(sum / degree_);
    breakpoints_.push_back(knots_.back());
  }
  knots_.insert(knots_.end(), degree_ + 1, params.back());
}

void OrientationCurve::set_keys(std::span<const glm::quat> keys) {
  if (keys.size() != t_.size())
    throw std::invalid_argument("quaternion curve: expected " + std::to_string(t_.size()) +
                                " keys, got " + std::to_string(keys.size()));
  for (std::size_t i = 0; i < keys.size(); ++i) set_key(static_cast<int>(i), keys[i]);
  finish_keys();
}

void OrientationCurve::finish_keys() {
  for (std::size_t i = 1; i < keys_.size(); ++i)
    if (glm::dot(keys_[i - 1], keys_[i]) < 0.0) keys_[i] = -keys_[i];
  if (kind_ == OrientationCurveKind::kSmooth)
    for (std::size_t i = 1; i < keys_.size(); ++i)
      log_turn_[i] = log_of(glm::normalize(glm::conjugate(keys_[i - 1]) * keys_[i]));
}

int OrientationCurve::piece(double t) const {
  const auto it = std::upper_bound(t_.begin() + 1, t_.end() - 1, t);
  return static_cast<int>(it - t_.begin()) - 1;
}

int OrientationCurve::cumulative_basis(double t, std::array<double, kMaxDegree + 1>& cumulative,
                                       std::array<double, kMaxDegree + 1>& slope) const {
  const int n = parameter_count() - 1, d = degree_;
  const auto it = std::upper_bound(knots_.begin() + d + 1, knots_.begin() + n + 1, t);
  const int span = static_cast<int>(it - knots_.begin()) - 1;
  double basis[kMaxDegree + 1], lower[kMaxDegree + 1];
  bspline_basis(knots_, span, d, t, basis);
  bspline_basis(knots_, span, d - 1, t, lower);
  // N'_{i,d} = d (N_{i,d-1} / (u_{i+d} - u_i) - N_{i+1,d-1} / (u_{i+d+1} - u_{i+1})), i = span-d+r.
  double derivative[kMaxDegree + 1];
  for (int r = 0; r <= d; ++r) {
    const int i = span - d + r;
    derivative[r] = 0.0;
    if (r >= 1) derivative[r] += d * lower[r - 1] / (knots_[i + d] - knots_[i]);
    if (r < d) derivative[r] -= d * lower[r] / (knots_[i + d + 1] - knots_[i + 1]);
  }
  cumulative[d] = basis[d];
  slope[d] = derivative[d];
  for (int r = d - 1; r >= 1; --r) {
    cumulative[r] = cumulative[r + 1] + basis[r];
    slope[r] = slope[r + 1] + derivative[r];
  }
  return span;
}

glm::dquat OrientationCurve::smooth_value(double t, glm::dquat* derivative) const {
  std::array<double, kMaxDegree + 1> cumulative{}, slope{};
  const int span = cumulative_basis(t, cumulative, slope);
  const int d = degree_, first = span - d;
  // Q = q_first E_1 … E_d with E_r = exp(ω_{first+r} B̃_{first+r}); E_r' = E_r ω B̃'.
  std::array<glm::dquat, kMaxDegree + 1> factor{}, prefix{};
  prefix[0] = keys_[first];
  for (int r = 1; r <= d; ++r) {
    factor[r] = exp_of(log_turn_[first + r] * cumulative[r]);
    prefix[r] = prefix[r - 1] * factor[r];
  }
  if (derivative) {
    glm::dquat sum(0.0, 0.0, 0.0, 0.0), suffix(1.0, 0.0, 0.0, 0.0);
    for (int r = d; r >= 1; --r) {
      const glm::dvec3 w = log_turn_[first + r] * slope[r];
      sum += prefix[r] * glm::dquat(0.0, w.x, w.y, w.z) * suffix;
      suffix = factor[r] * suffix;
    }
    *derivative = sum;
  }
  return prefix[d];
}

glm::dquat OrientationCurve::unnormalised(double t) const {
  if (kind_ == OrientationCurveKind::kSmooth) return smooth_value(t, nullptr);
  const int i = piece(t);
  const double s = (t - t_[i]) / (t_[i + 1] - t_[i]);
  return keys_[i] * (1.0 - s) + keys_[i + 1] * s;
}

glm::dquat OrientationCurve::derivative(double t) const {
  if (kind_ == OrientationCurveKind::kSmooth) {
    glm::dquat d;
    smooth_value(t, &d);
    return d;
  }
  const int i = piece(t);
  return (keys_[i + 1] - keys_[i]) / (t_[i + 1] - t_[i]);
}

glm::dquat OrientationCurve::unit(double t) const { return glm::normalize(unnormalised(t)); }

glm::dmat3 OrientationCurve::rotation(double t) const { return glm::mat3_cast(unit(t)); }

}  // namespace sweepd::deform
