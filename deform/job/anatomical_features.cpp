#include "deform/job/anatomical_features.h"

namespace sweepd::deform {

std::string to_string(const AnatomicalFeatures& features) {
  std::string list;
  auto add = [&](bool on, const char* name) {
    if (!on) return;
    if (!list.empty()) list += ',';
    list += name;
  };
  add(features.folding, "folding");
  add(features.protrusion, "protrusion");
  add(features.volume, "volume");
  add(features.bulge, "bulge");
  add(features.contact, "contact");
  return list;
}

}  // namespace sweepd::deform
