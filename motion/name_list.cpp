#include "motion/name_list.h"

#include <algorithm>

namespace sweepd::motion {

std::string name_list(std::span<const std::string> names, std::size_t shown) {
  std::string text;
  const std::size_t listed = std::min(names.size(), shown);
  for (std::size_t k = 0; k < listed; ++k) text += (k ? ", " : "") + names[k];
  if (names.size() > listed) text += " and " + std::to_string(names.size() - listed) + " more";
  return text;
}

}  // namespace sweepd::motion
