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

}  // namespace sweepd::deform
