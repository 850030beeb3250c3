// build_welcome: the Welcome reply to an accepted Hello — the protocol version, the server's
// name and capabilities ("position_map" only when position maps are enabled, "shared_memory"
// (1.10) only on a Unix socket, where MapSharedMemory works), its frame and
// in-flight limits and the connection's id. Finishes `builder` as one frame carrying
// `request_id`.
#pragma once

#include <cstdint>

#include "protocol/sweepd_generated.h"
#include "server/config.h"

namespace sweepd::server {

void build_welcome(flatbuffers::FlatBufferBuilder& builder, const ServerConfig& config,
                   bool position_maps, bool shared_memory, std::uint64_t connection_id,
                   std::uint64_t request_id);

}  // namespace sweepd::server
