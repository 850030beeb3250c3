// Content ids: what names a model in every replica of a fleet (issue 14 item 2). A model's
// content id is the SHA-256 (Debian's OpenSSL) of what its binding was made from — the glTF
// bytes (uploaded or read from the model directory), the client's rig map JSON and the bind
// options — as 64 lower-case hex digits. Its name is only a label: the same bytes and options
// give the same id on any replica, so a store shared by replicas holds each model once, and a
// client that knows the id can ask any replica for it.
//
// model_content_id(source, rig_map_json, keys_per_link): the id of a glTF binding (source:
//   the whole file, any size; rig_map_json: empty when detected; keys_per_link: 0 = default;
//   orientation: BindOptions.orientation, 0 = linear, which leaves the id as it was before).
// described_content_id(description): the id of a model made by the server itself from a
//   description (the procedural mannequin: "mannequin vertices=N").
// clip_content_id(bvh, length_scale, joint_name_map): the id of a motion clip (issue 18): the
//   BVH text and how it is read (scale, and the joint name map's JSON text when not empty), so
//   the same upload gives the same id on any replica.
// gltf_clip_content_id(gltf, animation, own_skeleton, joint_name_map): the id of a glTF
//   animation clip (protocol 1.7): the file's bytes, which animation (as the client named it),
//   whether it plays on the model's own joints, and the joint name map when not empty. Never
//   equal to a BVH clip's id (the first hashed part says which kind).
// range_of_motion_clip_id(model_content_id): the id of a model's range of motion (protocol 1.13,
//   motion/range_of_motion.h), built by the server from the model's skeleton and rig map, which
//   its content id names: the same model gives the same id on every replica. Never equal to an
//   uploaded clip's id.
// handle_of(content_id): the protocol's 32-bit model_id for it — its first 8 hex digits (0 is
//   never given: it means "not loaded" on the wire). The same on every replica, so a handle a
//   client got from one replica names the same model on another. Two ids with one handle are
//   possible (about n²/2³³ for n models); ModelRegistry refuses the second, saying so.
// is_content_id(text): 64 lower-case hex digits.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace sweepd::server {

std::string model_content_id(std::span<const std::uint8_t> source, std::string_view rig_map_json,
                             int keys_per_link, int orientation = 0);
std::string described_content_id(std::string_view description);
std::string clip_content_id(std::string_view bvh, float length_scale,
                            std::string_view joint_name_map = {});
std::string gltf_clip_content_id(std::span<const std::uint8_t> gltf, std::string_view animation,
                                 bool own_skeleton, std::string_view joint_name_map);
std::string range_of_motion_clip_id(std::string_view model_content_id);
std::uint32_t handle_of(std::string_view content_id);
bool is_content_id(std::string_view text);

}  // namespace sweepd::server
