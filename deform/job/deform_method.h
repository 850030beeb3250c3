// DeformMethod: how a pose becomes a deformed mesh — by control sweeps (the paper), or by the
// model's own skin weights with linear blend or dual-quaternion skinning (the baselines every
// quality and speed figure is compared against; clients may choose them too).
// to_string: "sweep", "lbs", "dqs" (deform/job/method_choice.h parses the names).
#pragma once

namespace sweepd::deform {

enum class DeformMethod { kSweep, kLbs, kDqs };
const char* to_string(DeformMethod method);

}  // namespace sweepd::deform
