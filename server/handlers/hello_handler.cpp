#include "server/handlers/hello_handler.h"

namespace sweepd::server {

namespace pb = sweepd::protocol;

void handle_hello(const pb::Message& message, RequestSession& session) {
  session.send_error(
      {pb::ErrorCode::InvalidArgument, "Hello was already received on this connection"},
      message.request_id());
}

}  // namespace sweepd::server
