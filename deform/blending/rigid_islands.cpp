#include "deform/blending/rigid_islands.h"

#include <algorithm>
#include <cstdint>

#include "deform/mesh/disjoint_sets.h"

namespace sweepd::deform {

std::vector<int> rigid_island_joints(const Model& model, const WeldedMesh& mesh) {
  const std::vector<std::uint32_t> component =
      vertex_components(mesh.indices, mesh.vertex_count());
  // Per component (indexed by its smallest welded id): its one joint, -1 until seen, -2 once
  // two joints or a blended vertex show.
  std::vector<int> joint_of(mesh.vertex_count(), -1);
  auto single_joint = [&](std::size_t v) {
    const int k = model.strongest_influence(v);
    return model.skin_weights[v][k] >= kRigidWeight ? static_cast<int>(model.skin_joints[v][k])
                                                     : -2;
  };
  for (std::size_t v = 0; v < model.vertex_count(); ++v) {
    int& joint = joint_of[component[mesh.welded_id[v]]];
    if (joint == -2) continue;
    const int own = single_joint(v);
    joint = joint == -1 || joint == own ? own : -2;
  }
  std::vector<int> result(model.vertex_count(), -1);
  for (std::size_t v = 0; v < model.vertex_count(); ++v)
    result[v] = std::max(-1, joint_of[component[mesh.welded_id[v]]]);
  return result;
}

}  // namespace sweepd::deform
