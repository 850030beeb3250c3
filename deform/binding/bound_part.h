// bound_part: the binding of some of a model's vertices alone, as a BoundModel of its own (no
// triangles): what a SweepPoser deforms when only those vertices are wanted. A vertex's posed
// position depends on its own binding and the sweeps alone, so the part's vertices pose exactly
// as they do in the whole model. What the binding's self-check deforms per candidate (the
// vertices a refitted sweep moves and their neighbours), where posing the whole body would cost
// more than the rest of the check.
// Inputs:  bound, vertices (model indices, each < vertex_count(), any order)
// Output:  a BoundModel whose vertex i is bound's vertices[i]: position, normal, skin influences,
//          binding and skinned-share influences copied; of the sweeps, those its vertices are
//          on, in bound's order (the bindings' sweep indices renumbered to match: a poser poses
//          no other); skeleton, rig and options as bound's; no key-ellipse edits (they name bound's
//          sweeps), indices, parts or UVs.
#pragma once

#include <cstdint>
#include <span>

#include "deform/binding/bound_model.h"

namespace sweepd::deform {

BoundModel bound_part(const BoundModel& bound, std::span<const std::uint32_t> vertices);

}  // namespace sweepd::deform
