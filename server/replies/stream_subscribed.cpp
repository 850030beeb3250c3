#include "server/replies/stream_subscribed.h"

#include "protocol/messages.h"

namespace sweepd::server {

void build_stream_subscribed(flatbuffers::FlatBufferBuilder& builder, const std::string& stream,
                             std::uint32_t model_id, std::uint64_t request_id) {
  namespace pb = sweepd::protocol;
  const auto reply = pb::CreateStreamSubscribed(builder, builder.CreateString(stream), model_id);
  pb::finish_message(builder, reply, request_id);
}

}  // namespace sweepd::server
