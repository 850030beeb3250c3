// Hello (after the first): the first Hello of a connection is its authentication, done by the
// transport (server/transport/connection.cpp); a second one is answered with InvalidArgument and
// the session goes on.
#pragma once

#include "protocol/sweepd_generated.h"
#include "server/handlers/request_session.h"

namespace sweepd::server {

void handle_hello(const protocol::Message& message, RequestSession& session);

}  // namespace sweepd::server
