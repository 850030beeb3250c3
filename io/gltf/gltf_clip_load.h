// load_gltf_clip: one animation of a glTF 2.0 file (.glb or .gltf) as a keyframed motion::Clip
// (motion/clip.h, motion/keyframe_track.h) whose joints are the file's skin joints — the same
// joints, names and order as io::load_gltf gives the model read from that file, so the clip
// plays on it joint for joint (motion::OwnSkeletonClip) or retargets onto another model like a
// BVH (motion::Retargeter).
//
// Input:  file   a .glb or .gltf (external URIs as io::load_gltf allows them); or its bytes in
//                memory (a client's upload, protocol 1.7) with a label naming them in messages:
//                self-contained, so only the GLB chunk and data: URIs are read and any other URI
//                is refused before a file is looked at (io/gltf/gltf_uri_policy.h), as for models
//         clip   the animation's name, or its index in the file ("0", "1", ...) when no
//                animation has that name
// Output: a Clip with
//         - joints: the skin of the node io::load_gltf loads (the skinned mesh with most
//           vertices; without a skinned mesh, the file's first skin), parents first, with rest
//           rotations and offsets; offsets and translation keys are in the scene's units (times
//           the scale of the joint's ancestors, e.g. 0.01 under a centimetre armature), and a
//           root's keys carry its non-joint ancestors' transform (a rotated armature), as its
//           rest transform does;
//         - tracks: the animation's rotation and translation channels on those joints, each
//           with its sampler's keys and interpolation (STEP, LINEAR, CUBICSPLINE);
//         - start_time, end_time: its first and last key; frame_time: the smallest interval
//           between two keys of one track (a clip baked at every frame of a 30 fps scene gets
//           1/30 s; 1/30 s when every track has one key); frame_count: the frames that fit.
//         Warnings (Clip::warnings) for what is not played: channels on nodes that are not the
//         skin's joints, morph-target weights, scale keys that differ from the rest scale.
// Throws io::LoadError naming the file and the problem: no animations, an unknown name or an
// index past the last (listing the file's animations), no skin, a channel or sampler that
// refers to nothing, an unknown interpolation, accessors of the wrong type or count, key times
// that do not increase, and everything io::load_gltf refuses in the file's structure.
//
// load_gltf_animations(file): every animation of the file from one parse, each with its name
// (file order, "" for one without) and its clip or why it cannot play (io/animation_choice.h), for
// listing them (sweepctl inspect); LoadError as load_gltf_clip's for a file tinygltf cannot read.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "io/animation_choice.h"
#include "io/gltf/gltf_uri_policy.h"
#include "motion/clip.h"

namespace sweepd::io {

motion::Clip load_gltf_clip(const std::filesystem::path& file, const std::string& clip);
motion::Clip load_gltf_clip(const std::filesystem::path& file, const std::string& clip,
                            const GltfUriPolicy& uris);
std::vector<FileAnimation> load_gltf_animations(const std::filesystem::path& file);
motion::Clip load_gltf_clip(std::span<const std::uint8_t> bytes, const std::filesystem::path& label,
                            const std::string& clip);

}  // namespace sweepd::io
