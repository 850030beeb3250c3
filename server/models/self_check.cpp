#include "server/models/self_check.h"

namespace sweepd::server {

SelfCheck self_check(const selfcheck::BindingVerdict& verdict) {
  SelfCheck checked;
  checked.poses = static_cast<int>(verdict.pose_names.size());
  checked.warnings = selfcheck::region_warnings(verdict);
  return checked;
}

SelfCheck self_check(const deform::BoundModel& bound) {
  return self_check(selfcheck::check_binding(bound, selfcheck::range_of_motion_peaks(bound)));
}

}  // namespace sweepd::server
