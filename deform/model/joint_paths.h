// Joint paths: ancestry queries on a Skeleton's hierarchy (parents-first joint order).
//
// Inputs are joint indices into Skeleton::joints; out-of-range indices give "no" answers
// (false, -1, an empty path) rather than undefined behaviour.
#pragma once

#include <vector>

#include "deform/model/skeleton.h"

namespace sweepd::deform {

// True when `ancestor` lies strictly above `joint` in the hierarchy.
bool is_strict_ancestor(const Skeleton& skeleton, int ancestor, int joint);

// The joints from `ancestor` down to `joint`, both included, ancestor first; {joint} when they
// are equal; empty when `ancestor` is not above `joint`.
std::vector<int> path_down(const Skeleton& skeleton, int ancestor, int joint);

// The deepest joint that is `a` or above it and also `b` or above it; -1 when none.
int common_ancestor(const Skeleton& skeleton, int a, int b);

}  // namespace sweepd::deform
