// MapSharedMemory (1.10): a sealed memfd region for the connection's pose replies
// (SharedRegion), its bytes taken from the server's buffer budget until the connection closes,
// its descriptor passed with the SharedMemory reply. Refused with NotAvailable off a Unix socket
// (a descriptor cannot cross TCP, TLS or WebSocket), InvalidArgument for a second region or a
// size outside 1..max_frame_bytes, ResourceExhausted when the budget or the kernel has no room.
#pragma once

#include "protocol/sweepd_generated.h"
#include "server/handlers/request_session.h"

namespace sweepd::server {

void handle_map_shared_memory(const protocol::Message& message, RequestSession& session);

}  // namespace sweepd::server
