// load_assimp_clip: one animation (an FBX animation stack, a COLLADA animation) of a file that
// libassimp reads, as a keyframed motion::Clip (motion/clip.h) whose joints are exactly those
// io::load_assimp gives the model read from the same bytes — names, parents, order and rest
// transforms (io/assimp/assimp_scene.h builds both) — so the clip plays on that model joint for joint
// (motion::OwnSkeletonClip) or retargets onto another model like a BVH (motion::Retargeter).
//
// Input:  bytes  the file's content; assimp reads these and no other file
//         label  names the file in messages
//         clip   the animation's name, or its index ("0", "1", ...) when none has that name
//                (io/animation_choice.h)
// Output: a Clip with
//         - joints: the model's skeleton, rest rotations and offsets (metres: FBX units applied
//           as for the model);
//         - tracks: for each joint the animation moves, a LINEAR rotation track and, where its
//           translation moves (by more than 1e-6 m), a LINEAR translation track. A joint's local
//           transform is made of several scene nodes: its own, the $AssimpFbx$ helper nodes that
//           carry its FBX transform parts (pre-rotation, pivots, ...) and any other node between
//           it and its parent joint (above a root: every ancestor). Its keys are at every key time
//           of those nodes' channels; at each, the nodes' transforms are composed — a node with a
//           channel at its keys interpolated as assimp plays them (positions and scales linearly,
//           rotations by slerp), a node without one at its rest transform — and split into
//           rotation and translation. assimp hands FBX curves over sampled at their keys, so the
//           clip equals the file's keys at key times (up to FBX's Euler-angle storage).
//         - times in seconds: assimp's ticks / the animation's ticks per second (25 when the file
//           gives none, as assimp itself assumes); frames as motion::Clip::set_keyframed_timing.
//         Warnings (Clip::warnings): channels on nodes outside the skeleton (not played), scale
//         that moves (not played: sweepd poses rotations and the root's translation).
// Throws io::LoadError naming the file and the problem: no animations, a name or index the file
// lacks (listing its animations), an animation that moves no joint, a key that is not finite, key
// times that do not increase, and everything io::load_assimp refuses in the scene.
//
// load_assimp_animations(bytes, label): every animation of the file from one import, each with its
// name (file order, "" for one without) and its clip or why it cannot play (io/animation_choice.h);
// LoadError as load_assimp_clip's for a file assimp cannot read.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "io/animation_choice.h"
#include "io/files/load_error.h"
#include "motion/clip.h"

namespace sweepd::io {

motion::Clip load_assimp_clip(std::span<const std::uint8_t> bytes,
                              const std::filesystem::path& label, const std::string& clip);
std::vector<FileAnimation> load_assimp_animations(std::span<const std::uint8_t> bytes,
                                                  const std::filesystem::path& label);

}  // namespace sweepd::io
