// PoseFromClip (1.4): a frame of an uploaded clip played on a held model
// (read_clip_pose_message), queued as a pose; a request without a pose or a clip is refused
// with InvalidArgument.
#pragma once

#include "protocol/sweepd_generated.h"
#include "server/handlers/request_session.h"

namespace sweepd::server {

void handle_pose_from_clip(const protocol::Message& message, RequestSession& session);

}  // namespace sweepd::server
