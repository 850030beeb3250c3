#include "deform/job/deform_method.h"

namespace sweepd::deform {

const char* to_string(DeformMethod method) {
  switch (method) {
    case DeformMethod::kSweep:
      return "sweep";
    case DeformMethod::kLbs:
      return "lbs";
    case DeformMethod::kDqs:
      return "dqs";
  }
  return "?";
}

std::optional<DeformMethod> parse_deform_method(std::string_view name) {
  for (DeformMethod m : {DeformMethod::kSweep, DeformMethod::kLbs, DeformMethod::kDqs})
    if (name == to_string(m)) return m;
  return std::nullopt;
}

}  // namespace sweepd::deform
