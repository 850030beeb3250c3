// bspline_basis: the B-spline basis functions that may be nonzero on one knot span
// (Cox–de Boor, Piegl & Tiller's algorithm A2.2), shared by the quadratic half-axis functions
// (interpolating_splines.h) and the cumulative B-spline orientation curve
// (orientation_curve.h).
// Inputs:  knots   the knot vector (non-decreasing)
//          span    k with knots[k] < knots[k+1] (the interval t lies in, or the end interval t
//                  extends)
//          degree  p, 0..3
//          t       the parameter; outside [knots[k], knots[k+1]] the span's polynomials continue
// Output:  basis   p+1 values N_{k-p..k, p}(t) in basis[0..p]
#pragma once

#include <span>

namespace sweepd::deform {

void bspline_basis(std::span<const double> knots, int span, int degree, double t, double* basis);

}  // namespace sweepd::deform
