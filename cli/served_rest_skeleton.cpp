#include "cli/served_rest_skeleton.h"

#include <stdexcept>

namespace sweepd::cli {

deform::Skeleton rest_skeleton(const protocol::ModelInfo& info) {
  const auto* names = info.joint_names();
  const auto* parents = info.joint_parents();
  const auto* translations = info.joint_rest_translations();
  const auto* rotations = info.joint_rest_rotations();
  const auto* scales = info.joint_rest_scales();
  if (!names || !parents || !translations || !rotations || !scales) {
    throw std::runtime_error("ModelInfo carries no rest skeleton (the server speaks protocol 1.0)");
  }
  const std::size_t count = names->size();
  if (parents->size() != count || translations->size() != count || rotations->size() != count ||
      scales->size() != count) {
    throw std::runtime_error("ModelInfo's joint arrays differ in length");
  }
  deform::Skeleton skeleton;
  for (std::size_t j = 0; j < count; ++j) {
    const protocol::Vec3 *t = translations->Get(j), *s = scales->Get(j);
    const protocol::Quat* r = rotations->Get(j);
    skeleton.joints.push_back({.name = names->Get(j)->str(),
                               .parent = parents->Get(j),
                               .rest_translation = {t->x(), t->y(), t->z()},
                               .rest_rotation = glm::quat(r->w(), r->x(), r->y(), r->z()),
                               .rest_scale = {s->x(), s->y(), s->z()}});
  }
  if (const std::string problem = skeleton.validate(); !problem.empty()) {
    throw std::runtime_error("ModelInfo's skeleton is unusable: " + problem);
  }
  return skeleton;
}

}  // namespace sweepd::cli
