#include "server/handlers/map_shared_memory_handler.h"

#include <memory>
#include <string>
#include <system_error>
#include <utility>

#include "protocol/messages.h"
#include "server/log_event.h"

namespace sweepd::server {

namespace pb = sweepd::protocol;

void handle_map_shared_memory(const pb::Message& message, RequestSession& session) {
  const std::uint64_t request_id = message.request_id();
  const std::uint64_t bytes = message.body_as_MapSharedMemory()->bytes();
  if (!session.unix_socket()) {
    session.send_error({pb::ErrorCode::NotAvailable,
                        "MapSharedMemory needs a Unix socket connection: a descriptor cannot "
                        "cross TCP, TLS or WebSocket"},
                       request_id);
    return;
  }
  if (const SharedRegion* region = session.shared_region()) {
    session.send_error({pb::ErrorCode::InvalidArgument,
                        "this connection has a shared region already (" +
                            std::to_string(region->size()) + " bytes); it maps one"},
                       request_id);
    return;
  }
  ConnectionEnvironment& environment = session.environment();
  const std::size_t limit = environment.config.max_frame_bytes;
  if (bytes == 0 || bytes > limit) {
    session.send_error(
        {pb::ErrorCode::InvalidArgument, "MapSharedMemory asks for " + std::to_string(bytes) +
                                             " bytes; a region has 1 to " + std::to_string(limit) +
                                             " (max_frame_bytes)"},
        request_id);
    return;
  }
  if (!environment.buffer_budget.take(bytes)) {
    session.send_error({pb::ErrorCode::ResourceExhausted,
                        "the server's buffer budget has no room for a shared region of " +
                            std::to_string(bytes) + " bytes now"},
                       request_id);
    return;
  }
  std::shared_ptr<const SharedRegion> region;
  try {
    region = SharedRegion::create(bytes);
  } catch (const std::system_error& error) {
    environment.buffer_budget.give_back(bytes);
    session.send_error(
        {pb::ErrorCode::ResourceExhausted,
         "cannot make a shared region of " + std::to_string(bytes) + " bytes: " + error.what()},
        request_id);
    return;
  }
  log_event("shared_memory_mapped", {{"connection", session.connection_id()}, {"bytes", bytes}});
  flatbuffers::FlatBufferBuilder builder = session.take_builder();
  pb::finish_message(builder, pb::CreateSharedMemory(builder, bytes), request_id);
  session.send_region(std::move(region), std::move(builder));
}

}  // namespace sweepd::server
