// upload_clip: keep a BVH clip on the server (UploadClip, protocol 1.4), so that frames are
// asked for by clip id and frame number (ClipFrame in PoseFromClip or PositionMapRequest)
// instead of a retargeted pose each — the server retargets, exactly as `sweepctl pose --bvh`.
//
//   const protocol::ClipInfo& info = upload_clip(connection, "walk.bvh", text, 0.056444f);
//   std::string clip_id = info.clip_id()->str();  // the same on every server for this text
//
// Inputs: an open connection after Hello; name (a label for the server's logs); the BVH text,
// whole; length_scale (metres per clip unit); joint_name_map, the JSON text of a joint name
// map (`sweepctl --bvh-map`, protocol 1.5), or empty. Output: the server's ClipInfo (clip id, frame
// count, frame rate, joint count, warnings), valid until the connection's next receive.
// Throws ServerError with the server's code: ClipLoadFailed (not a BVH: the line and reason),
// ClipLimit (the server holds as many clips as it may), FrameTooLarge (over max_frame_bytes),
// InvalidArgument (a joint name map that is not a JSON object of names).
// A server that later answers UnknownClip (restarted, or another replica) wants it again.
#pragma once

#include <string_view>

#include "client/connection.h"

namespace sweepd::client {

const protocol::ClipInfo& upload_clip(Connection& connection, std::string_view name,
                                      std::string_view bvh, float length_scale = 1.0f,
                                      std::string_view joint_name_map = {});

}  // namespace sweepd::client
