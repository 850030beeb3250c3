// DeformMethod: how a pose becomes a deformed mesh — by control sweeps (the paper), or by the
// model's own skin weights with linear blend or dual-quaternion skinning (the baselines every
// quality and speed figure is compared against; clients may choose them too).
// to_string / parse_deform_method: "sweep", "lbs", "dqs" (parse: nullopt for anything else).
#pragma once

#include <optional>
#include <string_view>

namespace sweepd::deform {

enum class DeformMethod { kSweep, kLbs, kDqs };
const char* to_string(DeformMethod method);
std::optional<DeformMethod> parse_deform_method(std::string_view name);

}  // namespace sweepd::deform
