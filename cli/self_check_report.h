// The binding's self-check in words (selfcheck/binding_self_check.h), as `sweepctl bind` and
// `sweepctl inspect FILE.sweepbind` print it: one line with the worse (pose, region) pairs and
// regions, a line per sweep the adaptation fitted again, and a warning per region still worse.
#pragma once

#include <optional>

#include "deform/binding/bound_model.h"
#include "selfcheck/binding_self_check.h"

namespace sweepd::cli {

// pairs_as_bound: the worse pairs before the adaptation, where it ran (printed beside the
// verdict's own).
void print_self_check(const deform::BoundModel& bound, const selfcheck::BindingVerdict& verdict,
                      std::optional<int> pairs_as_bound = {});

}  // namespace sweepd::cli
