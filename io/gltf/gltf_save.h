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
//         Animations (SaveOptions::animations): one glTF animation each, named as given, with
//         per track one sampler (input: the key times, a FLOAT SCALAR accessor with min/max,
//         shared by tracks with the same times; output: the values as FLOAT VEC4 x, y, z, w
//         for rotations, VEC3 for translations, written as given; interpolation LINEAR, STEP
//         or CUBICSPLINE from the track) and one channel targeting the track's joint's node,
//         path "rotation" or "translation". load_gltf_clip reads them back key for key
//         (translation keys times the scale of the joint's ancestors, as from any file).
// Throws std::invalid_argument when the model is invalid (the reason from Model::validate())
// or options do not match it (for animations: an empty or repeated name, no tracks, a joint out
// of range, a track that fails motion::track_problem (non-finite values among them), a negative
// key time, a CUBICSPLINE track of one key, a rotation that is not a unit quaternion within
// 1e-3, two tracks of one joint and path; the message names the animation, track and joint),
// std::runtime_error when the file cannot be written.
#pragma once

#include <filesystem>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "deform/model/model.h"
#include "motion/keyframe_track.h"

namespace sweepd::io {

// A keyframed clip on the model's own skeleton: each track's joint indexes
// model.skeleton.joints (the file's joint nodes 0..J-1).
struct SavedAnimation {
  std::string name;  // non-empty, unique in the file: load_gltf_clip chooses clips by name
  std::vector<motion::KeyframeTrack> tracks;
};

struct SaveOptions {
  // COLOR_0 per vertex (linear RGBA), e.g. to show binding regions in a viewer; empty = none.
  std::vector<glm::vec4> vertex_colors;
  // Closed polylines (>= 2 points each) written as an unskinned LINE_LOOP mesh, e.g. the key
  // ellipses of a binding; empty = none.
  std::vector<std::vector<glm::vec3>> line_loops;
  // Animations of the skeleton, e.g. a range-of-motion clip to play in a viewer; empty = none.
  std::vector<SavedAnimation> animations;
};

void save_gltf(const deform::Model& model, const std::filesystem::path& file,
               const SaveOptions& options = {});

}  // namespace sweepd::io
