// Pose: checked against its model by the pose intake (read_pose_message) and queued on the
// connection's pose queue, or refused with the intake's error.
#pragma once

#include "protocol/sweepd_generated.h"
#include "server/handlers/request_session.h"

namespace sweepd::server {

void handle_pose(const protocol::Message& message, RequestSession& session);

}  // namespace sweepd::server
