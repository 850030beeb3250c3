#include "deform/binding/bound_model.h"

namespace sweepd::deform {

std::vector<glm::vec3> BoundSweep::rest_path(std::span<const glm::mat4> world_rest) const {
  std::vector<glm::vec3> path;
  for (int j : chain) path.emplace_back(world_rest[j][3]);
  if (ends_on_carried_end()) path.push_back(rest_keys.back().centre);
  return path;
}

}  // namespace sweepd::deform
