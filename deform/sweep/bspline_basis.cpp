#include "deform/sweep/bspline_basis.h"

namespace sweepd::deform {

void bspline_basis(std::span<const double> knots, int span, int degree, double t, double* basis) {
  double left[4] = {}, right[4] = {};
  basis[0] = 1.0;
  for (int j = 1; j <= degree; ++j) {
    left[j] = t - knots[span + 1 - j];
    right[j] = knots[span + j] - t;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      const double temp = basis[r] / (right[r + 1] + left[j - r]);
      basis[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    basis[j] = saved;
  }
}

}  // namespace sweepd::deform
