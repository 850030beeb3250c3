#include "deform/sweep/swept_volume.h"

#include <algorithm>
#include <array>
#include <numbers>
#include <stdexcept>
#include <string>

namespace sweepd::deform {
namespace {

// 8-point Gauss–Legendre on [-1, 1]: symmetric nodes ±x_k with weights w_k.
constexpr std::array<double, 4> kGaussNodes = {0.1834346424956498, 0.5255324099163290,
                                               0.7966664774136267, 0.9602898564975363};
constexpr std::array<double, 4> kGaussWeights = {0.3626837833783620, 0.3137066458778873,
                                                 0.2223810344533745, 0.1012285362903763};

void require_size(std::span<const double> buffer, const Sweep& sweep, const char* name) {
  if (static_cast<int>(buffer.size()) != sweep.key_count())
    throw std::invalid_argument(std::string("sweep volume: ") + name + " has " +
                                std::to_string(buffer.size()) + " values, expected " +
                                std::to_string(sweep.key_count()));
}

// Adds the contribution of one quadrature point at t with weight w (already scaled to the
// interval) to the volume and, when the spans are non-empty, to the gradient.
double add_sample(const Sweep& sweep, double t, double w, std::span<double> d_alpha,
                  std::span<double> d_beta) {
  const glm::dvec3 normal = sweep.orientation_curve().rotation(t)[2];
  const double flux = w * std::numbers::pi * glm::dot(normal, sweep.ellipse_centre_derivative(t));
  const auto& a_fn = sweep.a_function();
  const auto& b_fn = sweep.b_function();
  std::array<double, InterpolatingQuadraticSpline::kMaxDegree + 1> a_basis{}, b_basis{};
  const int a_first = a_fn.nonzero_basis(t, a_basis);
  const int b_first = b_fn.nonzero_basis(t, b_basis);
  double a = 0.0, b = 0.0;
  for (int r = 0; r <= a_fn.degree(); ++r) a += a_basis[r] * a_fn.controls()[a_first + r];
  for (int r = 0; r <= b_fn.degree(); ++r) b += b_basis[r] * b_fn.controls()[b_first + r];
  if (!d_alpha.empty())
    for (int r = 0; r <= a_fn.degree(); ++r) d_alpha[a_first + r] += flux * a_basis[r] * b;
  if (!d_beta.empty())
    for (int r = 0; r <= b_fn.degree(); ++r) d_beta[b_first + r] += flux * b_basis[r] * a;
  return flux * a * b;
}

// 8-point Gauss–Legendre on [lo, hi].
double integrate_interval(const Sweep& sweep, double lo, double hi, std::span<double> d_alpha,
                          std::span<double> d_beta) {
  const double centre = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  double volume = 0.0;
  for (std::size_t k = 0; k < kGaussNodes.size(); ++k) {
    const double w = kGaussWeights[k] * half;
    volume += add_sample(sweep, centre - half * kGaussNodes[k], w, d_alpha, d_beta);
    volume += add_sample(sweep, centre + half * kGaussNodes[k], w, d_alpha, d_beta);
  }
  return volume;
}

double integrate(const Sweep& sweep, std::span<double> d_alpha, std::span<double> d_beta) {
  std::fill(d_alpha.begin(), d_alpha.end(), 0.0);
  std::fill(d_beta.begin(), d_beta.end(), 0.0);
  const auto t = sweep.parameters();
  // The orientation curve's own joints: the linear curve's are the keys; the smooth curve's
  // knots fall inside the halves, which are split there too.
  const auto breaks = sweep.orientation_curve().breakpoints();
  auto next_break = breaks.begin();
  double volume = 0.0;
  for (std::size_t i = 0; i + 1 < t.size(); ++i) {
    const double middle = 0.5 * (t[i] + t[i + 1]);
    for (const auto& [lo, hi] : {std::pair{t[i], middle}, std::pair{middle, t[i + 1]}}) {
      double from = lo;
      for (; next_break != breaks.end() && *next_break < hi; ++next_break)
        if (*next_break > from) {
          volume += integrate_interval(sweep, from, *next_break, d_alpha, d_beta);
          from = *next_break;
        }
      volume += integrate_interval(sweep, from, hi, d_alpha, d_beta);
    }
  }
  return volume;
}

}  // namespace

double sweep_volume(const Sweep& sweep) { return integrate(sweep, {}, {}); }

double sweep_volume_gradient(const Sweep& sweep, std::span<double> d_alpha,
                             std::span<double> d_beta) {
  require_size(d_alpha, sweep, "d_alpha");
  require_size(d_beta, sweep, "d_beta");
  return integrate(sweep, d_alpha, d_beta);
}

double volume_correction_step(const Sweep& sweep, double target_volume,
                              std::span<const int> controls, std::span<double> delta_alpha,
                              std::span<double> delta_beta) {
  return volume_correction_step(sweep, target_volume, controls, controls, delta_alpha, delta_beta);
}

double volume_correction_step(const Sweep& sweep, double target_volume,
                              std::span<const int> alpha_controls,
                              std::span<const int> beta_controls, std::span<double> delta_alpha,
                              std::span<double> delta_beta) {
  for (std::span<const int> controls : {alpha_controls, beta_controls})
    for (int c : controls)
      if (c < 0 || c >= sweep.key_count())
        throw std::invalid_argument("sweep volume: control index " + std::to_string(c) +
                                    " out of range [0, " + std::to_string(sweep.key_count()) + ")");
  const double volume = sweep_volume_gradient(sweep, delta_alpha, delta_beta);
  auto active = [](std::span<const int> controls, int i) {
    return std::find(controls.begin(), controls.end(), i) != controls.end();
  };
  double norm2 = 0.0;
  for (int c : alpha_controls) norm2 += delta_alpha[c] * delta_alpha[c];
  for (int c : beta_controls) norm2 += delta_beta[c] * delta_beta[c];
  const double scale = norm2 > 0.0 ? (target_volume - volume) / norm2 : 0.0;
  for (int i = 0; i < sweep.key_count(); ++i) {
    delta_alpha[i] = active(alpha_controls, i) ? scale * delta_alpha[i] : 0.0;
    delta_beta[i] = active(beta_controls, i) ? scale * delta_beta[i] : 0.0;
  }
  return volume;
}

void apply_half_axis_deltas(Sweep& sweep, std::span<const double> delta_alpha,
                            std::span<const double> delta_beta) {
  require_size(delta_alpha, sweep, "delta_alpha");
  require_size(delta_beta, sweep, "delta_beta");
  for (int i = 0; i < sweep.key_count(); ++i) {
    sweep.alpha()[i] += delta_alpha[i];
    sweep.beta()[i] += delta_beta[i];
  }
}

}  // namespace sweepd::deform
