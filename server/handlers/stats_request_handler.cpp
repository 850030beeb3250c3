#include "server/handlers/stats_request_handler.h"

#include <utility>

#include "server/elapsed_time.h"
#include "server/replies/stats_reply.h"

namespace sweepd::server {

namespace pb = sweepd::protocol;

void handle_stats_request(const pb::Message& message, RequestSession& session) {
  ConnectionEnvironment& environment = session.environment();
  flatbuffers::FlatBufferBuilder builder = session.take_builder();
  build_stats(builder, nanoseconds_since(environment.started), environment.models.models(),
              environment.model_counters, environment.all_counters(),
              environment.collision.snapshot(), message.request_id());
  session.send(std::move(builder));
}

}  // namespace sweepd::server
