// save_gltf: writes a deform::Model as a binary glTF 2.0 file (.glb) that the Khronos
// glTF-Validator accepts with 0 errors, and that load_gltf reads back to the same Model.
//
// Input:  model    a Model that passes Model::validate() (n vertices, J joints)
//         file     destination path (written whole; an existing file is replaced)
//         options  optional extras (see SaveOptions)
// Output: one .glb with a scene of J joint nodes (name = joint name, rest TRS) and one mesh
//         node per mesh: a model without parts is one skinned mesh named after the model; a
//         model with parts (deform/model/mesh_part.h) gets one mesh per run of parts with the
//         same MeshPart::mesh, named MeshPart::name (its node too), one primitive per part.
//         Skinned meshes' nodes are scene roots with the skin; a rigid part's node is a child
//         of its joint's node, its vertices in that joint's rest frame, without JOINTS/WEIGHTS.
//         Per primitive: POSITION (with min/max), NORMAL, TEXCOORD_0 (when the model has UVs),
//         JOINTS_0 (u8 when J <= 256, else u16), WEIGHTS_0 (float, renormalised in float so
//         each vertex sums to 1 within the validator's tolerance, unused slots use joint 0),
//         u32 indices; inverse bind matrices = inverse(world rest). Materials: one per distinct
//         MeshPart::material name (unnamed: "skin"), each the same plain default (only the
//         name is the file's: colours, textures and PBR factors are not kept).
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
