// MethodChoice: the deformation methods that sweepctl's comparing commands (metrics, sheet) take
// by name in their --method(s) list, and one deformation of a pose with such a method here.
//   methods_by_name   "sweep", "sweep+volume" (volume preservation), "sweep+features" (folding
//                     and protrusion), "sweep+contact" (those and whole-body contact), "lbs",
//                     "dqs"
//   deform_with       runs one deform::DeformJob of `pose` with the method into positions
//                     (vertex_count() each) and, when not empty, normals; folding's pairs from
//                     `collision` (null: the CPU reference). Returns the context's SweepPoser
//                     posed to the pose: the deformation's own sweep state for sweep methods,
//                     the section planes for LBS/DQS. The context's world_pose() is the pose's.
#pragma once

#include <glm/glm.hpp>
#include <map>
#include <span>
#include <string>

#include "cli/local_collision.h"
#include "deform/job/deform_job.h"

namespace sweepd::cli {

struct MethodChoice {
  std::string name;
  deform::DeformMethod method;
  bool preserve_volume;
  bool collision = false;  // folding and protrusion, their pairs from --collision's backend
  bool contact = false;    // whole-body contact too (with collision), the same backend
};

const std::map<std::string, MethodChoice>& methods_by_name();

const deform::SweepPoser& deform_with(const MethodChoice& m, const deform::ModelRuntime& runtime,
                                      deform::DeformContext& context, LocalCollision* collision,
                                      deform::Pose pose, std::span<glm::vec3> positions,
                                      std::span<glm::vec3> normals = {});

}  // namespace sweepd::cli
