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
  // A builder a position map or a contact sheet grew is freed: kept, every idle builder could
  // come to hold a frame's worth of memory that no budget counts (issue 49 item 2).
  if (builder.GetSize() > kLargestKeptBytes) return;
  if (idle_.size() < cap()) idle_.push_back(std::move(builder));
}

void ReplyBuilderPool::set_connections(std::size_t count) {
  connections_ = count;
  if (idle_.size() > cap())
    idle_.erase(idle_.begin() + static_cast<std::ptrdiff_t>(cap()), idle_.end());
}

}  // namespace sweepd::server
