#include "deform/binding/rest_sweep.h"

namespace sweepd::deform {

Sweep rest_sweep(const BoundSweep& sweep, const BindOptions& options) {
  return Sweep(sweep.rest_keys, options.centre_curve, sweep.choice.orientation_curve);
}

}  // namespace sweepd::deform
