// The one table of requests: each message type a client may send, and the handler that answers
// it (server/handlers/<request>_handler.h). The connection authenticates (the first Hello),
// checks every client-chosen string's bound (client_string_limits.h) and then hands the message
// to its handler; a type with no handler is answered with UnknownMessage.
#pragma once

#include "protocol/sweepd_generated.h"
#include "server/handlers/request_session.h"

namespace sweepd::server {

using RequestHandler = void (*)(const protocol::Message& message, RequestSession& session);

// The handler of a message of type `type`, or nullptr for a type this server does not answer.
RequestHandler handler_for(protocol::Body type);

}  // namespace sweepd::server
