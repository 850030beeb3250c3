// Swept volume of a Sweep and the volume-preserving update of its half-axis controls
// (paper §3.1 and §4.4).
//
//   I(α, β) = ∫_0^1 a(t) b(t) π <N(t), C̃'(t)> dt,   a = Σ α_i A_i(t), b = Σ β_i B_i(t)
// where A_i, B_i are the quadratic B-spline bases of the sweep's a(t), b(t) and C̃ is the
// ellipses' centre curve (Sweep::ellipse_centre): the volume a moving planar section sweeps is
// its area times the normal speed of its centroid (the turn about the centroid sweeps as much
// forwards as backwards). C̃' = C' + R' (o, 0) + R (o', 0); the last term lies in the plane, so
// only the turning offset R' (o, 0) adds to C'. I is bilinear in (α, β), so
// ∂I/∂α_i = ∫ A_i b π <N, C̃'> dt and ∂I/∂β_i = ∫ a B_i π <N, C̃'> dt exactly.
// Quadrature: every key span [t_i, t_{i+1}] is split at its midpoint (the a/b knots) and each
// half gets 8-point Gauss–Legendre. The integrand is a degree-8 polynomial over the positive
// quadratic |Q(t)|^2 (zero offsets; an offset adds a rational term of the same kind), so the
// polynomial part is integrated exactly and the rational part to
// better than 1e-10 relative for neighbouring keys up to 150 degrees apart (checked against a
// 2e6-point midpoint rule).
// With the smooth orientation curve (OrientationCurveKind::kSmooth) the halves are split again
// at its knots and N(t) holds sines and cosines of polynomials, so no rule is exact: against a
// 2e6-point midpoint rule the relative error stays below 1e-9 for keys up to 150 degrees apart
// (tests/deform/sweep/swept_volume_test.cpp).
// The volume is the signed one: positive when N points along C̃'.
#pragma once

#include <span>

#include "deform/sweep/sweep.h"

namespace sweepd::deform {

// I for the sweep's current curves and controls.
double sweep_volume(const Sweep& sweep);

// I and its gradient: d_alpha[i] = ∂I/∂α_i, d_beta[i] = ∂I/∂β_i.
// d_alpha, d_beta: key_count() values each (caller-owned). Returns I. No allocation.
double sweep_volume_gradient(const Sweep& sweep, std::span<double> d_alpha,
                             std::span<double> d_beta);

// One step of the paper's update, restricted to the control indices in `controls` (e.g. first
// the joint's key ellipse, then its neighbours as well):
//   (Δα, Δβ) = (target - I) / (Σ_{i in controls} (∂I/∂α_i)^2 + (∂I/∂β_i)^2) · ∇I|_controls,
// zero outside `controls`. delta_alpha, delta_beta: key_count() values each (caller-owned).
// Returns the volume I before the step. A zero restricted gradient gives zero deltas.
// Throws std::invalid_argument for a control index out of range or wrong buffer sizes.
double volume_correction_step(const Sweep& sweep, double target_volume,
                              std::span<const int> controls, std::span<double> delta_alpha,
                              std::span<double> delta_beta);

// The same with separate control sets for α and β (e.g. a bent joint's key corrected only
// along the half-axis that does not lie in the bend plane). An index in neither is frozen.
double volume_correction_step(const Sweep& sweep, double target_volume,
                              std::span<const int> alpha_controls,
                              std::span<const int> beta_controls, std::span<double> delta_alpha,
                              std::span<double> delta_beta);

// α += delta_alpha, β += delta_beta (sizes key_count()).
void apply_half_axis_deltas(Sweep& sweep, std::span<const double> delta_alpha,
                            std::span<const double> delta_beta);

}  // namespace sweepd::deform
