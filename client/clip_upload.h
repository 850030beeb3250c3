// upload_clip: keep a BVH clip on the server (UploadClip, protocol 1.4), so that frames are
// asked for by clip id and frame number (ClipFrame in PoseFromClip or PositionMapRequest)
// instead of a retargeted pose each — the server retargets, exactly as `sweepctl pose --bvh`.
//
//   const protocol::ClipInfo& info = upload_clip(connection, "walk.bvh", text, 0.056444f);
//   std::string clip_id = info.clip_id()->str();  // the same on every server for this text
//
// Inputs: an open connection after Hello; name (a label for the server's logs); the BVH text,
// whole; length_scale (metres per clip unit); joint_name_map, the JSON text of a joint name
// map (`sweepctl --bvh-map`, protocol 1.5), or empty; model_id (protocol 1.12), the model the
// clip will play on (ModelInfo.model_id), or none. Output: the server's ClipInfo (clip id, frame
// count, frame rate, joint count, warnings: the reader's, and with model_id each of playing it
// on that model, "on model 'NAME': ..." naming the joints left unmapped on either side; a 1.11
// server ignores model_id), valid until the connection's next receive.
// Throws ServerError with the server's code: ClipLoadFailed (not a BVH: the line and reason),
// ClipLimit (the server holds as many clips as it may), FrameTooLarge (over max_frame_bytes),
// InvalidArgument (a joint name map that is not a JSON object of names).
// A server that later answers UnknownClip (restarted, or another replica) wants it again.
//
// upload_gltf_clip (protocol 1.7; Welcome.capabilities has "gltf_clips"): the same for an
// animation of a glTF file — gltf, the whole .glb (or a .gltf whose buffers are data: URIs: the
// server reads nothing else); animation, its name or index ("" for the first); own_skeleton,
// true to play it joint for joint on the model's own joints (a clip of the model's own file, as
// `sweepctl pose MODEL.glb --clip`), false to retarget it (as `--clip-from`). Throws
// ServerError: ClipLoadFailed naming the problem (not a glTF, a truncated GLB, an external URI,
// no animations, an unknown name listing the file's animations, an animation that drives none
// of the skin's joints), ClipLimit, FrameTooLarge, InvalidArgument; a 1.6 server answers
// ClipLoadFailed (it reads the absent BVH text). Since protocol 1.8 (capability "fbx_clips") the
// bytes may be an FBX or COLLADA file's instead: its animation stacks, read by the server with
// io::load_assimp_clip; a 1.7 server answers ClipLoadFailed (not a glTF file).
//
// upload_range_of_motion (protocol 1.13): no clip bytes — the server builds the held model's
// range of motion (motion/range_of_motion.h: each joint of its rig map through its anatomical
// range, 1 s a move at 30 fps; 1,441 frames for a full rig) and plays it on the model's own
// joints; `sweepctl rom` writes the same clip. model_id: the model (ModelInfo.model_id), whose
// content id is part of the clip id. Throws ServerError: UnknownModel (naming the models the
// server holds), ClipLimit; a 1.12 server ignores the field and answers ClipLoadFailed (it reads
// the absent BVH text).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include "client/connection.h"

namespace sweepd::client {

const protocol::ClipInfo& upload_clip(Connection& connection, std::string_view name,
                                      std::string_view bvh, float length_scale = 1.0f,
                                      std::string_view joint_name_map = {},
                                      std::optional<std::uint32_t> model_id = std::nullopt);
const protocol::ClipInfo& upload_gltf_clip(Connection& connection, std::string_view name,
                                           std::span<const std::uint8_t> gltf,
                                           std::string_view animation, bool own_skeleton,
                                           std::string_view joint_name_map = {},
                                           std::optional<std::uint32_t> model_id = std::nullopt);
const protocol::ClipInfo& upload_range_of_motion(Connection& connection, std::uint32_t model_id);

}  // namespace sweepd::client
