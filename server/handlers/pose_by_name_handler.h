// PoseByName (1.4): rotations keyed by joint name (read_named_pose_message), queued as a
// pose; a request without a pose is refused with InvalidArgument.
#pragma once

#include "protocol/sweepd_generated.h"
#include "server/handlers/request_session.h"

namespace sweepd::server {

void handle_pose_by_name(const protocol::Message& message, RequestSession& session);

}  // namespace sweepd::server
