// StatsRequest: the server's uptime, per model and per connection counters, and the collision
// backend's (Stats, server/replies/stats_reply.h), built at once on the I/O thread.
#pragma once

#include "protocol/sweepd_generated.h"
#include "server/handlers/request_session.h"

namespace sweepd::server {

void handle_stats_request(const protocol::Message& message, RequestSession& session);

}  // namespace sweepd::server
