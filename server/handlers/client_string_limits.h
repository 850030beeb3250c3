// The bounds on every string a client chooses and the daemon keeps, logs, stores or echoes in an
// Error, checked in one place as each request arrives (before it is authenticated for Hello, so
// an over-long client name never reaches a log line). A string over its bound is refused with
// InvalidArgument naming the field, its length and the bound; the connection is served on.
//
//   kMaxPathBytes 4096     LoadModel.name: a client may send its local path (PATH_MAX); with
//                          bytes the server keeps the base name, without them the name is a
//                          store or model directory name, either held to 200 bytes by the
//                          model service (the store adds suffixes to it within NAME_MAX 255).
//   kMaxNameBytes 255      Hello.client_name, UploadClip.name and .animation,
//                          EditKeyEllipse.sweep, PoseByName.joint_names[i],
//                          ContactSheetRequest.methods[i] and .focus, SubscribeStream.stream
//                          (echoed when no stream has it): NAME_MAX, so a label
//                          taken from a file's name always fits, and each is one field of a log
//                          line or an Error message, never a page of it.
//   kMaxContentIdBytes 64  LoadModel.content_id, ClipFrame.clip_id (in PoseFromClip and
//                          PositionMapRequest), ContactSheetRequest.clip_id: a SHA-256 in hex.
//   kMaxJsonBytes 32 KiB   BindOptions.rig_map_json, UploadClip.joint_name_map: a map of every
//                          joint of a 200-joint rig to a 64-byte name fits in half of it; each
//                          key and string inside is a joint name, bounded by kMaxNameBytes.
//
// The HTTP side port holds the viewer's file names (/viewer/NAME, echoed in its 404) to
// kMaxNameBytes too, refused with 414.
//
// Not bounded here: Hello.auth_token (compared, never kept or shown), Bye.reason (not read), and
// UploadClip.bvh and .gltf (the clip itself, bounded by max_frame_bytes and the clip store).
#pragma once

#include <cstddef>
#include <optional>

#include "protocol/sweepd_generated.h"
#include "server/handlers/request_error.h"

namespace sweepd::server {

inline constexpr std::size_t kMaxNameBytes = 255;
inline constexpr std::size_t kMaxPathBytes = 4096;
inline constexpr std::size_t kMaxContentIdBytes = 64;
inline constexpr std::size_t kMaxJsonBytes = 32 * 1024;

// The first client-chosen string of `message` over its bound, as the InvalidArgument to answer
// (carrying the pose's sequence for a pose request); nullopt when every one fits.
std::optional<RequestError> find_overlong_string(const protocol::Message& message);

}  // namespace sweepd::server
