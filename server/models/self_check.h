// The binding's self-check as a model holds it (ModelInfo 1.14, the bind_warning log): the
// range-of-motion poses judged and each region where the sweep is still worse than skinning
// (selfcheck/binding_self_check.h). Derived from a binding: checked at bind and at each edit,
// stored beside it (self_check_sidecar.h) and read back at restore.
#pragma once

#include <vector>

#include "deform/binding/bound_model.h"
#include "selfcheck/binding_self_check.h"

namespace sweepd::server {

struct SelfCheck {
  int poses = 0;  // 0: not checked
  std::vector<selfcheck::RegionWarning> warnings;
  bool operator==(const SelfCheck&) const = default;
};
// Runs it on `bound` (selfcheck::check_binding on its range-of-motion peaks; the shared male
// 14.5k vertices about 0.06 s).
SelfCheck self_check(const deform::BoundModel& bound);
SelfCheck self_check(const selfcheck::BindingVerdict& verdict);  // a verdict already made

}  // namespace sweepd::server
