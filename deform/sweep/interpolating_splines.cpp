#include "deform/sweep/interpolating_splines.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "deform/sweep/bspline_basis.h"

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
  span_second_.assign(2 * n, glm::dvec3(0.0));
  // C''(t_1) .. C''(t_{n-1}) of the C2 kinds; the local kind solves nothing.
  const int unknowns = ends_ == SplineEnds::kLocal ? 0 : std::max(n - 1, 0);
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
  if (ends_ == SplineEnds::kLocal)
    local_second_derivatives();
  else
    global_second_derivatives();
}

void InterpolatingCubicSpline::global_second_derivatives() {
  const int n = static_cast<int>(t_.size()) - 1;
  std::fill(second_.begin(), second_.end(), glm::dvec3(0.0));
  auto h = [&](int i) { return t_[i + 1] - t_[i]; };
  if (n >= 2) {
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
  for (int i = 0; i < n; ++i) {
    span_second_[2 * i] = second_[i];
    span_second_[2 * i + 1] = second_[i + 1];
  }
}

void InterpolatingCubicSpline::local_second_derivatives() {
  const int n = static_cast<int>(t_.size()) - 1;
  auto h = [&](int i) { return t_[i + 1] - t_[i]; };
  auto slope = [&](int i) { return (points_[i + 1] - points_[i]) / h(i); };
  // Tangents: Bessel at interior knots (the parabola through three neighbours), and at the ends
  // the parabola through the first/last three points; a single span is the segment.
  auto tangent = [&](int i) {
    if (n == 1) return slope(0);
    if (i == 0) return 2.0 * slope(0) - (h(1) * slope(0) + h(0) * slope(1)) / (h(0) + h(1));
    if (i == n)
      return 2.0 * slope(n - 1) -
             (h(n - 1) * slope(n - 2) + h(n - 2) * slope(n - 1)) / (h(n - 2) + h(n - 1));
    return (h(i) * slope(i - 1) + h(i - 1) * slope(i)) / (h(i - 1) + h(i));
  };
  glm::dvec3 start_tangent = tangent(0);
  for (int i = 0; i < n; ++i) {
    const glm::dvec3 end_tangent = tangent(i + 1);
    const double hi = h(i);
    const glm::dvec3 d = slope(i);
    span_second_[2 * i] = (6.0 * d - 4.0 * start_tangent - 2.0 * end_tangent) / hi;
    span_second_[2 * i + 1] = (-6.0 * d + 2.0 * start_tangent + 4.0 * end_tangent) / hi;
    start_tangent = end_tangent;
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
  return c.w[0] * points_[i] + c.w[1] * points_[i + 1] + c.w[2] * span_second_[2 * i] +
         c.w[3] * span_second_[2 * i + 1];
}

glm::dvec3 InterpolatingCubicSpline::derivative(double t) const {
  const int i = span_of(t);
  const double h = t_[i + 1] - t_[i];
  const double u = t_[i + 1] - t, v = t - t_[i];
  const glm::dvec3& s0 = span_second_[2 * i];
  const glm::dvec3& s1 = span_second_[2 * i + 1];
  return (s1 * (v * v) - s0 * (u * u)) / (2.0 * h) + (points_[i + 1] - points_[i]) / h -
         (s1 - s0) * (h / 6.0);
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
  bspline_basis(knots_, k, p, t, basis.data());
  return k - p;
}

double InterpolatingQuadraticSpline::value(double t) const {
  std::array<double, kMaxDegree + 1> basis{};
  const int first = nonzero_basis(t, basis);
  double sum = 0.0;
  for (int r = 0; r <= degree_; ++r) sum += basis[r] * controls_[first + r];
  return sum;
}

double InterpolatingQuadraticSpline::derivative(double t) const {
  // f' = Σ p (c_i - c_{i-1}) / (u_{i+p} - u_i) N_{i,p-1}: on the span [u_k, u_{k+1}] the
  // degree-(p-1) basis is 1 (p = 1) or the two hat pieces (p = 2).
  std::array<double, kMaxDegree + 1> basis{};
  const int p = degree_;
  const int k = nonzero_basis(t, basis) + p;
  auto slope = [&](int i) {
    return p * (controls_[i] - controls_[i - 1]) / (knots_[i + p] - knots_[i]);
  };
  if (p == 1) return slope(k);
  const double s = (t - knots_[k]) / (knots_[k + 1] - knots_[k]);
  return (1.0 - s) * slope(k - 1) + s * slope(k);
}

}  // namespace sweepd::deform
