// Rest transforms as the model loaders (io/gltf/gltf_load, io/assimp/assimp_load) turn a file's matrices into
// deform::Joint fields and carry a file's vertices into the bind pose.
//
// decompose_rest_transform
// Input:  m       an affine 4x4 matrix (column-major, glm), local to the joint's parent
// Output: joint   rest_translation, rest_rotation (unit quaternion) and signed rest_scale; shear
//                 is dropped. False when a scale is zero (no inverse bind matrix exists).
// finite_rest_transform: whether every one of the joint's 10 rest numbers is finite.
// normal_matrix: columns a1 x a2, a2 x a0, a0 x a1 of the 3x3 part of `skin` — det * inverse
//   transpose, which carries normals through a (possibly singular) blended skinning matrix.
#pragma once

#include <glm/glm.hpp>

#include "deform/model/skeleton.h"

namespace sweepd::io {

bool decompose_rest_transform(const glm::dmat4& m, deform::Joint& joint);
bool finite_rest_transform(const deform::Joint& joint);
glm::dmat3 normal_matrix(const glm::dmat4& skin);

}  // namespace sweepd::io
