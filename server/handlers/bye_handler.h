// Bye from the client: the work already received is finished and answered, then the
// connection closes (RequestSession::drain).
#pragma once

#include "protocol/sweepd_generated.h"
#include "server/handlers/request_session.h"

namespace sweepd::server {

void handle_bye(const protocol::Message& message, RequestSession& session);

}  // namespace sweepd::server
