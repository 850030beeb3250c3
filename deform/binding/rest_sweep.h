// rest_sweep: the control sweep of a bound sweep's rest key ellipses (paper §3.2), with the
// centre curve the binding options chose and the orientation curve of the sweep's own choice. Posing, volume preservation, collision
// regions and edits all start from it; it needs the bound model's data only, not the binder.
//
// Inputs:  sweep    a BoundSweep (its rest_keys, at least two; choice.orientation_curve)
//          options  the BindOptions it was bound with (centre_curve)
// Output:  the Sweep through those keys.
#pragma once

#include "deform/binding/bound_model.h"
#include "deform/sweep/sweep.h"

namespace sweepd::deform {

Sweep rest_sweep(const BoundSweep& sweep, const BindOptions& options);

}  // namespace sweepd::deform
