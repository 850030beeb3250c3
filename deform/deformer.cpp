#include "deform/deformer.h"

#include <stdexcept>

#include "deform/dual_quaternion_skinning.h"
#include "deform/forward_kinematics.h"
#include "deform/linear_blend_skinning.h"

namespace sweepd::deform {

const char* to_string(DeformMethod method) {
  switch (method) {
    case DeformMethod::kSweep: return "sweep";
    case DeformMethod::kLbs: return "lbs";
    case DeformMethod::kDqs: return "dqs";
  }
  return "?";
}

std::optional<DeformMethod> parse_deform_method(std::string_view name) {
  for (DeformMethod m : {DeformMethod::kSweep, DeformMethod::kLbs, DeformMethod::kDqs})
    if (name == to_string(m)) return m;
  return std::nullopt;
}

Deformer::Deformer(const BoundModel& bound)
    : bound_(bound),
      sweep_poser_(bound),
      world_rest_inverse_(world_rest_inverse_matrices(bound.model.skeleton)),
      world_pose_(bound.model.skeleton.joints.size()),
      skinning_(bound.model.skeleton.joints.size()) {}

void Deformer::deform(Pose& pose, DeformMethod method, std::span<glm::vec3> positions,
                      std::span<glm::vec3> normals, int threads) {
  const Model& model = bound_.model;
  if (std::string why = normalize_and_validate(pose, model.skeleton); !why.empty())
    throw std::invalid_argument("invalid pose: " + why);
  if (positions.size() != model.vertex_count() ||
      (!normals.empty() && normals.size() != model.vertex_count()))
    throw std::invalid_argument("output buffers must hold " +
                                std::to_string(model.vertex_count()) + " vertices");
  forward_kinematics(model.skeleton, pose, world_pose_);
  skinning_matrices(world_pose_, world_rest_inverse_, skinning_);
  switch (method) {
    case DeformMethod::kSweep:
      sweep_poser_.set_pose(world_pose_);
      sweep_poser_.deform(skinning_, positions, normals, threads);
      break;
    case DeformMethod::kLbs:
      linear_blend_skinning_parallel(model, skinning_, positions, normals, threads);
      break;
    case DeformMethod::kDqs:
      dual_quaternion_skinning_parallel(model, skinning_, positions, normals, threads);
      break;
  }
}

}  // namespace sweepd::deform
