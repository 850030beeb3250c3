#include "deform/job/method_choice.h"

#include <stdexcept>

namespace sweepd::deform {

const std::map<std::string, MethodChoice>& methods_by_name() {
  static const std::map<std::string, MethodChoice> methods = {
      {"sweep", {"sweep", DeformMethod::kSweep, false}},
      {"sweep+volume", {"sweep+volume", DeformMethod::kSweep, true}},
      {"sweep+features", {"sweep+features", DeformMethod::kSweep, false, true}},
      {"sweep+contact", {"sweep+contact", DeformMethod::kSweep, false, true, true}},
      {"lbs", {"lbs", DeformMethod::kLbs, false}},
      {"dqs", {"dqs", DeformMethod::kDqs, false}}};
  return methods;
}

namespace {

bool is_plain(const MethodChoice& m) { return !m.preserve_volume && !m.collision && !m.contact; }

bool accepted(const MethodChoice& m, MethodNames names) {
  return names == MethodNames::kAll || is_plain(m);
}

}  // namespace

std::string method_name_problem(std::string_view name, MethodNames names) {
  const auto& known = methods_by_name();
  const auto found = known.find(std::string(name));
  if (found != known.end() && accepted(found->second, names)) return "";
  std::string listing;
  for (const auto& [known_name, m] : known)
    if (accepted(m, names)) listing += (listing.empty() ? "" : ", ") + known_name;
  return "unknown method '" + std::string(name) + "' (methods: " + listing + ")";
}

const MethodChoice& parse_method_choice(std::string_view name, MethodNames names) {
  if (const std::string problem = method_name_problem(name, names); !problem.empty())
    throw std::invalid_argument(problem);
  return methods_by_name().at(std::string(name));
}

}  // namespace sweepd::deform
