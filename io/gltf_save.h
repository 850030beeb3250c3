// save_gltf: writes a deform::Model as a binary glTF 2.0 file (.glb) that the Khronos
// glTF-Validator accepts with 0 errors, and that load_gltf reads back to the same Model.
//
// Input:  model    a Model that passes Model::validate() (n vertices, J joints)
//         file     destination path (written whole; an existing file is replaced)
//         options  optional extras (see SaveOptions)
// Output: one .glb with a scene of J joint nodes (name = joint name, rest TRS) and one skinned
//         mesh node; attributes POSITION (with min/max), NORMAL, TEXCOORD_0 (when the model has
//         UVs), JOINTS_0 (u8 when J <= 256, else u16), WEIGHTS_0 (float, renormalised in float
//         so each vertex sums to 1 within the validator's tolerance, unused slots use joint 0),
//         u32 indices, inverse bind matrices = inverse(world rest), a plain default material.
// Throws std::invalid_argument when the model is invalid (the reason from Model::validate())
// or options do not match it, std::runtime_error when the file cannot be written.
#pragma once

#include <filesystem>
#include <glm/glm.hpp>
#include <vector>

#include "deform/model/model.h"

namespace sweepd::io {

struct SaveOptions {
  // COLOR_0 per vertex (linear RGBA), e.g. to show binding regions in a viewer; empty = none.
  std::vector<glm::vec4> vertex_colors;
  // Closed polylines (>= 2 points each) written as an unskinned LINE_LOOP mesh, e.g. the key
  // ellipses of a binding; empty = none.
  std::vector<std::vector<glm::vec3>> line_loops;
};

void save_gltf(const deform::Model& model, const std::filesystem::path& file,
               const SaveOptions& options = {});

}  // namespace sweepd::io
