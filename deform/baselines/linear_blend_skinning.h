// Linear blend skinning (LBS): the baseline deformation with the model's own 4 skin weights —
// each vertex moves by the weighted sum of its joints' skinning matrices.
//
//   model      rest positions, normals and skin influences (deform/model/model.h)
//   skinning   skeleton.size() matrices from skinning_matrices (deform/model/forward_kinematics.h)
//   positions  vertex_count() posed positions (output, caller-owned)
//   normals    vertex_count() posed unit normals (output), or empty to skip them. Normals are
//              turned by the blended matrix's 3×3 part and renormalised (exact for rotations;
//              under non-uniform joint scale this is an approximation).
// Weights are divided by their sum, so the rest pose gives the rest mesh even where a file's
// weights sum to slightly less or more than 1. No allocation; the parallel variant splits the
// vertices into `threads` blocks (deform/simd/vertex_blocks.h) with bit-identical results.
#pragma once

#include <glm/glm.hpp>
#include <span>

#include "deform/model/model.h"

namespace sweepd::deform {

void linear_blend_skinning(const Model& model, std::span<const glm::mat4> skinning,
                           std::span<glm::vec3> positions, std::span<glm::vec3> normals);

void linear_blend_skinning_parallel(const Model& model, std::span<const glm::mat4> skinning,
                                    std::span<glm::vec3> positions, std::span<glm::vec3> normals,
                                    int threads);

}  // namespace sweepd::deform
