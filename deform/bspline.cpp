#include "deform/bspline.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sweepd::deform {
namespace {

void require_increasing(std::span<const double> t, const char* what) {
  if (t.size() < 2)
    throw std::invalid_argument(std::string(what) + ": need at least 2 parameters, got " +
                                std::to_string(t.size()));
  for (std::size_t i = 0; i + 1 < t.size(); ++i)
    if (!(t[i] < t[i + 1]) || !std::isfinite(t[i]) || !std::isfinite(t[i + 1]))
      throw std::invalid_argument(std::string(what) +
                                  ": parameters must be finite and strictly increasing (index " +
                                  std::to_string(i) + ")");
}

// Thomas factorisation of a diagonally dominant tridiagonal matrix given as rows
// (lower[i], diag[i], upper[i]). Leaves pivots in diag and the scaled upper diagonal in upper.
void factor_tridiagonal(std::span<const double> lower, std::span<double> diag,
                        std::span<double> upper) {
  for (std::size_t i = 0; i < diag.size(); ++i) {
    if (i > 0) diag[i] -= lower[i] * upper[i - 1];
    upper[i] /= diag[i];
  }
}

// Solves in place with the factors from factor_tridiagonal.
template <typename T>
void solve_tridiagonal(std::span<const double> lower, std::span<const double> pivot,
                       std::span<const double> upper, std::span<T> rhs) {
  const std::size_t m = rhs.size();
  for (std::size_t i = 0; i < m; ++i) {
    if (i > 0) rhs[i] -= lower[i] * rhs[i - 1];
    rhs[i] /= pivot[i];
  }
  for (std::size_t i = m - 1; i-- > 0;) rhs[i] -= upper[i] * rhs[i + 1];
}

}  // namespace

bool chord_length_parameters(std::span<const glm::vec3> points, std::span<double> params) {
  if (points.size() < 2 || params.size() != points.size()) return false;
  double total = 0.0;
  for (std::size_t i = 1; i < points.size(); ++i) {
    const double step = glm::length(glm::dvec3(points[i]) - glm::dvec3(points[i - 1]));
    if (!(step > 0.0)) return false;
    total += step;
  }
  double running = 0.0;
  params[0] = 0.0;
  for (std::size_t i = 1; i < points.size(); ++i) {
    running += glm::length(glm::dvec3(points[i]) - glm::dvec3(points[i - 1]));
    params[i] = running / total;
  }
  params.back() = 1.0;
  return true;
}

// ---- cubic ----------------------------------------------------------------------------------

void InterpolatingCubicSpline::set_parameters(std::span<const double> params, SplineEnds ends) {
  require_increasing(params, "cubic spline");
  ends_ = ends;
  t_.assign(params.begin(), params.end());
  const int n = static_cast<int>(t_.size()) - 1;
  points_.assign(n + 1, glm::dvec3(0.0));
  second_.assign(n + 1, glm::dvec3(0.0));
  const int unknowns = std::max(n - 1, 0);  // C''(t_1) .. C''(t_{n-1})
  lower_.assign(unknowns, 0.0);
  pivot_.assign(unknowns, 0.0);
  upper_.assign(unknowns, 0.0);
  rhs_.assign(unknowns, glm::dvec3(0.0));
  if (unknowns == 0) return;
  auto h = [&](int i) { return t_[i + 1] - t_[i]; };
  // Row i (1..n-1): h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1} = r_i.
  for (int i = 1; i <= n - 1; ++i) {
    lower_[i - 1] = h(i - 1);
    pivot_[i - 1] = 2.0 * (h(i - 1) + h(i));
    upper_[i - 1] = h(i);
  }
  if (ends_ == SplineEnds::kNotAKnot) {
    if (n == 2) {
      // One interior knot: the parabola, M_0 = M_1 = M_2.
      pivot_[0] = 3.0 * (h(0) + h(1));
    } else {
      // Substitute M_0 = ((h0 + h1) M_1 - h0 M_2) / h1 into row 1 ...
      const double h0 = h(0), h1 = h(1);
      pivot_[0] = 2.0 * (h0 + h1) + h0 * (h0 + h1) / h1;
      upper_[0] = h1 - h0 * h0 / h1;
      // ... and M_n = ((a + b) M_{n-1} - b M_{n-2}) / a into row n-1 (a = h_{n-2}, b = h_{n-1}).
      const double a = h(n - 2), b = h(n - 1);
      lower_[n - 2] = a - b * b / a;
      pivot_[n - 2] = 2.0 * (a + b) + b * (a + b) / a;
    }
  }
  factor_tridiagonal(lower_, pivot_, upper_);
}

void InterpolatingCubicSpline::interpolate(std::span<const glm::vec3> points) {
  if (points.size() != t_.size())
    throw std::invalid_argument("cubic spline: expected " + std::to_string(t_.size()) +
                                " points, got " + std::to_string(points.size()));
  const int n = static_cast<int>(t_.size()) - 1;
  for (int i = 0; i <= n; ++i) points_[i] = glm::dvec3(points[i]);
  std::fill(second_.begin(), second_.end(), glm::dvec3(0.0));
  if (n < 2) return;
  auto h = [&](int i) { return t_[i + 1] - t_[i]; };
  for (int i = 1; i <= n - 1; ++i)
    rhs_[i - 1] =
        6.0 * ((points_[i + 1] - points_[i]) / h(i) - (points_[i] - points_[i - 1]) / h(i - 1));
  solve_tridiagonal<glm::dvec3>(lower_, pivot_, upper_, rhs_);
  for (int i = 1; i <= n - 1; ++i) second_[i] = rhs_[i - 1];
  if (ends_ == SplineEnds::kNotAKnot) {
    if (n == 2) {
      second_[0] = second_[2] = second_[1];
    } else {
      const double h0 = h(0), h1 = h(1), a = h(n - 2), b = h(n - 1);
      second_[0] = ((h0 + h1) * second_[1] - h0 * second_[2]) / h1;
      second_[n] = ((a + b) * second_[n - 1] - b * second_[n - 2]) / a;
    }
  }
}

int InterpolatingCubicSpline::span_of(double t) const {
  const auto it = std::upper_bound(t_.begin() + 1, t_.end() - 1, t);
  return static_cast<int>(it - t_.begin()) - 1;
}

InterpolatingCubicSpline::Weights InterpolatingCubicSpline::weights(double t) const {
  Weights result;
  const int i = result.span = span_of(t);
  const double h = t_[i + 1] - t_[i];
  const double u = t_[i + 1] - t, v = t - t_[i];
  result.w = {u / h, v / h, (u * u * u / h - h * u) / 6.0, (v * v * v / h - h * v) / 6.0};
  return result;
}

glm::dvec3 InterpolatingCubicSpline::position(double t) const {
  const Weights c = weights(t);
  const int i = c.span;
  return c.w[0] * points_[i] + c.w[1] * points_[i + 1] + c.w[2] * second_[i] +
         c.w[3] * second_[i + 1];
}

glm::dvec3 InterpolatingCubicSpline::derivative(double t) const {
  const int i = span_of(t);
  const double h = t_[i + 1] - t_[i];
  const double u = t_[i + 1] - t, v = t - t_[i];
  return (second_[i + 1] * (v * v) - second_[i] * (u * u)) / (2.0 * h) +
         (points_[i + 1] - points_[i]) / h - (second_[i + 1] - second_[i]) * (h / 6.0);
}

// ---- quadratic ------------------------------------------------------------------------------

void InterpolatingQuadraticSpline::set_parameters(std::span<const double> sites) {
  require_increasing(sites, "quadratic spline");
  const int n = static_cast<int>(sites.size()) - 1;
  degree_ = std::min(kMaxDegree, n);
  const int p = degree_;
  knots_.clear();
  knots_.insert(knots_.end(), p + 1, sites.front());
  if (p == 2)
    for (int i = 2; i <= n - 1; ++i) knots_.push_back(0.5 * (sites[i - 1] + sites[i]));
  knots_.insert(knots_.end(), p + 1, sites.back());
  controls_.assign(n + 1, 0.0);
  lower_.assign(n + 1, 0.0);
  pivot_.assign(n + 1, 0.0);
  upper_.assign(n + 1, 0.0);
  // Row i: the basis functions at site t_i; by the knot choice only columns i-1, i, i+1 are
  // nonzero, so the matrix is tridiagonal.
  std::array<double, kMaxDegree + 1> basis{};
  for (int i = 0; i <= n; ++i) {
    const int first = nonzero_basis(sites[i], basis);
    for (int r = 0; r <= p; ++r) {
      const int column = first + r;
      if (column == i - 1) lower_[i] = basis[r];
      if (column == i) pivot_[i] = basis[r];
      if (column == i + 1) upper_[i] = basis[r];
    }
  }
  factor_tridiagonal(lower_, pivot_, upper_);
}

void InterpolatingQuadraticSpline::interpolate(std::span<const double> values) {
  if (values.size() != controls_.size())
    throw std::invalid_argument("quadratic spline: expected " + std::to_string(controls_.size()) +
                                " values, got " + std::to_string(values.size()));
  std::copy(values.begin(), values.end(), controls_.begin());
  solve_tridiagonal<double>(lower_, pivot_, upper_, controls_);
}

int InterpolatingQuadraticSpline::nonzero_basis(double t,
                                                std::array<double, kMaxDegree + 1>& basis) const {
  const int p = degree_;
  const int last_span = static_cast<int>(controls_.size()) - 1;
  // Span k with knots[k] <= t < knots[k+1], clamped to the valid spans [p, n].
  const auto it = std::upper_bound(knots_.begin() + p + 1, knots_.begin() + last_span + 1, t);
  const int k = static_cast<int>(it - knots_.begin()) - 1;
  // Cox–de Boor (Piegl & Tiller, algorithm A2.2).
  std::array<double, kMaxDegree + 1> left{}, right{};
  basis[0] = 1.0;
  for (int j = 1; j <= p; ++j) {
    left[j] = t - knots_[k + 1 - j];
    right[j] = knots_[k + j] - t;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      const double temp = basis[r] / (right[r + 1] + left[j - r]);
      basis[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    basis[j] = saved;
  }
  return k - p;
}

double InterpolatingQuadraticSpline::value(double t) const {
  std::array<double, kMaxDegree + 1> basis{};
  const int first = nonzero_basis(t, basis);
  double sum = 0.0;
  for (int r = 0; r <= degree_; ++r) sum += basis[r] * controls_[first + r];
  return sum;
}

}  // namespace sweepd::deform
