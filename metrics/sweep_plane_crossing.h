// Sweep plane crossing: where a posed sweep runs backwards through itself, turning the skin
// inside out on the inside of a deep bend (issue 47's "torn belly").
//
// A point bound to a sweep at (t, θ, displacement) moves as P(t) = C̃(t) + R(t) ℓ, ℓ its place
// in the moving ellipse's frame. The derivatives of P across the ellipse lie in its plane, so
// the sweep's map from (t, ℓ) to space has the sign of its Jacobian in the forward speed
//   f = N(t) · ∂P/∂t = N · C̃' + (R ℓ) · (N × ω)        (ω: the frame's turn per unit t):
// the speed of the centre along the normal, less |N × ω| times the point's distance d from the
// centre towards the inside of the bend. f < 0 exactly where the bend's radius N · C̃' / |N × ω|
// is smaller than d: there the neighbouring ellipse planes have crossed and the skin bound to
// them is turned inside out. The rest pose has f > 0 at every bound point of every shared body,
// so the ratio f_pose / f_rest per (vertex, sweep term) says how far a pose compressed the skin
// along the sweep (1: as at rest; towards 0: crowded; below 0: reversed).
// Measured (tests/metrics/sweep_plane_crossing_test.cpp, deform/README.md): the cause of most
// of the triangles the sweep flips and skinning does not on the heavy male and the child, not
// of those on the heavy and the OpenPose female.
// Inputs:  a BoundModel (outlives the meter); per measurement the posed sweeps (SweepPoser).
// Output:  per vertex the least ratio over its sweep terms (#V; 1 where no sweep moves it).
#pragma once

#include <array>
#include <span>
#include <vector>

#include "deform/binding/bound_model.h"
#include "deform/posing/sweep_poser.h"
#include "deform/sweep/sweep.h"

namespace sweepd::metrics {

// f = N(t) · ∂P/∂t of the point bound at `coordinate`, by central differences of
// deform::evaluate_point over t ± 2e-4 (the ends extend the sweep's end pieces).
double forward_speed(const deform::Sweep& sweep, const deform::SweepCoordinate& coordinate);
// The same of a posed sweep as its poser evaluates it: with its frame turned where the plane
// turn limit (deform/posing/plane_turn_limit.h) turned the table's rows.
double forward_speed(const deform::SweepPoser& posed, int sweep,
                     const deform::SweepCoordinate& coordinate);

class PlaneCrossingMeter {
 public:
  explicit PlaneCrossingMeter(const deform::BoundModel& bound);
  // Per vertex: the least f_pose / f_rest over its sweep terms of non-zero weight, f_pose as the
  // poser evaluates the sweep (its frames turned by the plane turn limit where it acted).
  std::vector<double> speed_ratios(const deform::SweepPoser& posed) const;
  // The least rest speed f_rest over every sweep term (> 0: no plane crosses a bound point at
  // rest).
  double least_rest_speed() const;

 private:
  const deform::BoundModel& bound_;
  std::vector<std::array<double, deform::kSweepsPerVertex>> rest_speed_;  // per vertex, term
};

}  // namespace sweepd::metrics
