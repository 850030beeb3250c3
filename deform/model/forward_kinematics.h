// Forward kinematics: a Pose on a Skeleton to world joint matrices, and the skinning matrices
// that move rest-pose vertices with the joints.
//
// forward_kinematics
//   Inputs:  skeleton (parents first), pose (normalize_and_validate'd, see deform/model/pose.h)
//   Output:  world   skeleton.size() matrices, world[j] = world[parent] * T_j * R_j * S_j with
//                    R_j the pose's local rotation, T_j the rest translation (the root's from
//                    the pose) and S_j the rest scale. One pass in joint order.
// skinning_matrices
//   Inputs:  world_pose          J world matrices from forward_kinematics
//            world_rest_inverse  J inverse world rest matrices (world_rest_inverse_matrices)
//   Output:  skinning            J matrices world_pose[j] * inverse(world_rest[j]); by the Model
//                                invariant (deform/model/model.h) the world rest matrices are the bind
//                                matrices, so these move rest vertices to posed ones.
// Both write into caller-owned buffers and allocate nothing.
#pragma once

#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "deform/model/pose.h"
#include "deform/model/skeleton.h"

namespace sweepd::deform {

void forward_kinematics(const Skeleton& skeleton, const Pose& pose, std::span<glm::mat4> world);

// Inverse world rest matrix of every joint (computed once per model, not per frame).
std::vector<glm::mat4> world_rest_inverse_matrices(const Skeleton& skeleton);

void skinning_matrices(std::span<const glm::mat4> world_pose,
                       std::span<const glm::mat4> world_rest_inverse,
                       std::span<glm::mat4> skinning);

}  // namespace sweepd::deform
