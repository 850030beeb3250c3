// The threads bind and SweepRebinder::rebind bind the vertices' coordinates on (each vertex
// alone, so the binding does not depend on the count): a pair, the cores of the machine issue
// 47's bind time is measured on; more would take cores a daemon's other workers serve with.
// Its own header so that the stages bind runs (blending, the self-check) take the count
// without bind's whole interface.
#pragma once

namespace sweepd::deform {

inline constexpr int kBindThreads = 2;

}  // namespace sweepd::deform
