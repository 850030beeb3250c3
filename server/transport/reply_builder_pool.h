// ReplyBuilderPool: the FlatBuffers builders replies are built in, shared by every connection
// of a server instead of kept per connection. A pose reply of the 72k mannequin grows its
// builder to 0.85 MB; kept per connection (as before), idle buffers grew the daemon's memory
// with every client. The pool keeps at most `capacity` idle builders for all of them; the rest
// are freed when their reply is written (sweepd sets glibc's mmap threshold so such buffers go
// back to the system, server/main.cpp).
//
// take():             a cleared builder, reused or new (1 KiB to start).
// give_back(builder): keeps it for the next take() while fewer than `capacity` are idle.
// Used on the server's I/O thread only (not thread-safe).
#pragma once

#include <flatbuffers/flatbuffers.h>

#include <cstddef>
#include <vector>

namespace sweepd::server {

class ReplyBuilderPool {
 public:
  explicit ReplyBuilderPool(std::size_t capacity) : capacity_(capacity) {}

  flatbuffers::FlatBufferBuilder take();
  void give_back(flatbuffers::FlatBufferBuilder builder);

  std::size_t idle() const { return idle_.size(); }

 private:
  std::size_t capacity_;
  std::vector<flatbuffers::FlatBufferBuilder> idle_;
};

}  // namespace sweepd::server
