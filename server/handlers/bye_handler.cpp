#include "server/handlers/bye_handler.h"

#include "server/log_event.h"

namespace sweepd::server {

namespace pb = sweepd::protocol;

void handle_bye(const pb::Message& /*message*/, RequestSession& session) {
  log_event("bye_received", {{"connection", session.connection_id()}});
  session.drain();
}

}  // namespace sweepd::server
