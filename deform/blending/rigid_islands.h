// Rigid islands (issue 47 item 4): connected pieces of the mesh that the model's own skinning
// moves rigidly — every vertex weighted to one and the same joint (armour plates, props, a
// robot's segments, eyes). Skinning keeps them rigid; a sweep bends them with the limb under
// them (a knee plate smeared over the bent knee, a plate inflated with the limb's volume). The
// binding leaves them to skinning, so they move exactly as their joint does.
//
// An island is a connected piece of the welded mesh (coincident vertices joined: a plate
// stitched to the skin is part of the skin, not an island). Its vertices are rigid when each
// has weight >= kRigidWeight on that one joint.
// Inputs: model (n vertices), mesh (the model welded: weld_mesh).
// Output: per model vertex, the joint whose rigid island it lies on, or -1.
#pragma once

#include <vector>

#include "deform/mesh/welded_mesh.h"
#include "deform/model/model.h"

namespace sweepd::deform {

// Painted weights of 1.0 arrive as 0.9999 after 8-bit or 16-bit quantisation in a file.
inline constexpr float kRigidWeight = 0.999f;

std::vector<int> rigid_island_joints(const Model& model, const WeldedMesh& mesh);

}  // namespace sweepd::deform
