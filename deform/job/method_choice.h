// MethodChoice: a deformation method as its users name it — sweepctl's --method, the comparing
// commands' method lists (metrics, check, sheet), the daemon's ContactSheetRequest and
// render_frames' --method. This is the one parser of those names.
//
//   methods_by_name()         every name and what it means: "sweep", "sweep+volume" (volume
//                             preservation), "sweep+features" (folding and protrusion),
//                             "sweep+contact" (those and whole-body contact), "lbs", "dqs"
//   method_name_problem(name, names)
//                             "" for a name accepted, else "unknown method 'NAME' (methods: dqs,
//                             lbs, sweep, ...)", listing the names accepted. names: every name,
//                             or kPlainMethods (sweep, lbs, dqs: a pose's method, whose features
//                             are chosen apart)
//   parse_method_choice(name, names)
//                             the choice named; std::invalid_argument with that message for
//                             any other name
#pragma once

#include <map>
#include <string>
#include <string_view>

#include "deform/job/deform_method.h"

namespace sweepd::deform {

struct MethodChoice {
  std::string name;
  DeformMethod method;
  bool preserve_volume;
  bool collision = false;  // folding and protrusion
  bool contact = false;    // whole-body contact too (with collision)
};

const std::map<std::string, MethodChoice>& methods_by_name();

enum class MethodNames { kAll, kPlainMethods };
std::string method_name_problem(std::string_view name, MethodNames names = MethodNames::kAll);
const MethodChoice& parse_method_choice(std::string_view name,
                                        MethodNames names = MethodNames::kAll);

}  // namespace sweepd::deform
