// build_stream_subscribed: the StreamSubscribed reply to a SubscribeStream (protocol 1.15) — the
// stream's name and the model it poses. Finishes `builder` as one frame carrying `request_id`.
#pragma once

#include <cstdint>
#include <string>

#include "protocol/sweepd_generated.h"

namespace sweepd::server {

void build_stream_subscribed(flatbuffers::FlatBufferBuilder& builder, const std::string& stream,
                             std::uint32_t model_id, std::uint64_t request_id);

}  // namespace sweepd::server
