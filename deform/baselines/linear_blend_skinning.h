// Linear blend skinning (LBS): the baseline deformation with the model's own 4 skin weights —
// each vertex moves by the weighted sum of its joints' skinning matrices.
//
//   table      the model's influences laid out once (skinning_table.h; ModelRuntime holds one)
//   skinning   table.joint_count() matrices from skinning_matrices
//              (deform/model/forward_kinematics.h)
//   positions  table.vertex_count() posed positions (output, caller-owned)
//   normals    table.vertex_count() posed unit normals (output), or empty to skip them. Normals
//              are turned by the blended matrix's 3×3 part and renormalised (exact for
//              rotations; under non-uniform joint scale this is an approximation).
//   threads    the items are split into this many blocks (deform/simd/vertex_blocks.h); results
//              are bit-identical for every count.
// The weights were divided by their sum when the table was built, so the rest pose gives the rest
// mesh even where a file's weights sum to slightly less or more than 1. No allocation but the
// threads'. The Model overload builds a table on the spot, for one-off calls.
#pragma once

#include <glm/glm.hpp>
#include <span>

#include "deform/baselines/skinning_table.h"
#include "deform/model/model.h"

namespace sweepd::deform {

void linear_blend_skinning(const SkinningTable& table, std::span<const glm::mat4> skinning,
                           std::span<glm::vec3> positions, std::span<glm::vec3> normals,
                           int threads = 1);

void linear_blend_skinning(const Model& model, std::span<const glm::mat4> skinning,
                           std::span<glm::vec3> positions, std::span<glm::vec3> normals);

}  // namespace sweepd::deform
