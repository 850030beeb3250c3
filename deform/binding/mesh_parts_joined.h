// mesh_parts_joined: which of a model's mesh parts (deform/model/mesh_part.h) the binding treats
// as one body, swept where the body is, and which it keeps as separate pieces that follow the
// model's own skin weights alone (LBS), so that a visor or a prop never joins a sweep's
// cross-sections.
//
// Touch: two parts touch when they share a vertex position exactly (the welded seam of one skin
// split into meshes; the equality weld_coincident_positions uses, mesh/mesh_topology.h).
// The body: the skinned part with the most vertices, and every skinned part that touches the
// body, transitively. A part parented rigidly to a joint (MeshPart::rigid_joint >= 0) follows
// its joint and never joins.
//
// Input:  model  passes Model::validate(); #V vertices, #K parts (none: one mesh, the body)
// Output: mesh_parts_joined: #K flags, 1 where the part joins the body;
//         vertices_joined: #V flags, 1 where the vertex's part joins (all 1 without parts).
#pragma once

#include <cstdint>
#include <vector>

#include "deform/model/model.h"

namespace sweepd::deform {

std::vector<std::uint8_t> mesh_parts_joined(const Model& model);
std::vector<std::uint8_t> vertices_joined(const Model& model);

}  // namespace sweepd::deform
