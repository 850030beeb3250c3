#include "server/transport/reply_builder_pool.h"

namespace sweepd::server {

flatbuffers::FlatBufferBuilder ReplyBuilderPool::take() {
  if (idle_.empty()) return flatbuffers::FlatBufferBuilder(1024);
  flatbuffers::FlatBufferBuilder builder = std::move(idle_.back());
  idle_.pop_back();
  builder.Clear();
  return builder;
}

void ReplyBuilderPool::give_back(flatbuffers::FlatBufferBuilder builder) {
  if (idle_.size() < capacity_) idle_.push_back(std::move(builder));
}

}  // namespace sweepd::server
