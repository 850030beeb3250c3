#include "deform/binding/bound_part.h"

namespace sweepd::deform {

BoundModel bound_part(const BoundModel& bound, std::span<const std::uint32_t> vertices) {
  BoundModel part;
  part.model.name = bound.model.name;
  part.model.skeleton = bound.model.skeleton;
  part.rig = bound.rig;
  part.options = bound.options;
  // The sweeps its vertices are on, renumbered in bound's order: a poser poses no other.
  std::vector<bool> used(bound.sweeps.size(), false);
  for (const std::uint32_t v : vertices)
    for (const std::int16_t s : bound.vertices[v].sweep)
      if (s >= 0) used[s] = true;
  std::vector<int> renumbered(bound.sweeps.size(), -1);
  for (std::size_t s = 0; s < bound.sweeps.size(); ++s)
    if (used[s]) {
      renumbered[s] = static_cast<int>(part.sweeps.size());
      part.sweeps.push_back(bound.sweeps[s]);
    }
  const bool own_share = !bound.skinned_share_joints.empty();
  for (const std::uint32_t v : vertices) {
    part.model.positions.push_back(bound.model.positions[v]);
    if (!bound.model.normals.empty()) part.model.normals.push_back(bound.model.normals[v]);
    part.model.skin_joints.push_back(bound.model.skin_joints[v]);
    part.model.skin_weights.push_back(bound.model.skin_weights[v]);
    part.vertices.push_back(bound.vertices[v]);
    for (std::int16_t& s : part.vertices.back().sweep)
      if (s >= 0) s = static_cast<std::int16_t>(renumbered[s]);
    if (own_share) {
      part.skinned_share_joints.push_back(bound.skinned_share_joints[v]);
      part.skinned_share_weights.push_back(bound.skinned_share_weights[v]);
    }
  }
  return part;
}

}  // namespace sweepd::deform
