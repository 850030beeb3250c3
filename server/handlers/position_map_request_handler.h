// PositionMapRequest: its pose (or clip frame, 1.4) checked by the pose intake with the map's
// size, layers and compression, and queued as a pose answered with a PositionMap (EXR); a
// request without a pose is refused with InvalidArgument.
#pragma once

#include "protocol/sweepd_generated.h"
#include "server/handlers/request_session.h"

namespace sweepd::server {

void handle_position_map_request(const protocol::Message& message, RequestSession& session);

}  // namespace sweepd::server
