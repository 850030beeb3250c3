// The animations part of io::save_gltf (internal to io/): SaveOptions::animations checked
// against the model's skeleton, then written as glTF 2.0 animations on its joint nodes.
//
// animations_problem(animations, skeleton): "" when every animation can be written as a file the
//   Khronos glTF-Validator accepts and load_gltf_clip reads by name; else the first problem in
//   words, naming the animation, the track (index, path) and the joint: an empty or repeated
//   name, no tracks, a joint out of range, motion::track_problem's reasons (no keys, times not
//   increasing, a wrong value count, non-finite numbers), a negative key time, a CUBICSPLINE
//   track of one key, a rotation value that is not a unit quaternion within 1e-3, two tracks of
//   one joint and path.
// add_animations(builder, gltf, animations): one glTF animation per SavedAnimation, a sampler
//   and a channel per track (target node = the track's joint: nodes 0..J-1 are the joints).
//   Tracks with equal key times share one input accessor. Requires animations_problem() == "".
#pragma once

#include <tiny_gltf.h>

#include <string>
#include <vector>

#include "deform/model/skeleton.h"
#include "io/gltf/glb_builder.h"
#include "io/gltf/gltf_save.h"

namespace sweepd::io {

std::string animations_problem(const std::vector<SavedAnimation>& animations,
                               const deform::Skeleton& skeleton);
void add_animations(GlbBuilder& builder, tinygltf::Model& gltf,
                    const std::vector<SavedAnimation>& animations);

}  // namespace sweepd::io
