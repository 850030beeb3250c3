// ReplyBuilderPool: the FlatBuffers builders replies are built in, shared by every connection
// of a server instead of kept per connection. A pose reply of the 72k mannequin grows its
// builder to 0.85 MB; kept per connection (as before), idle buffers grew the daemon's memory
// with every client. The pool keeps at most `base` idle builders plus one per open connection;
// the rest are freed when their reply is written (sweepd sets glibc's mmap threshold so such
// buffers go back to the system, server/main.cpp), and a closing connection's share is freed.
// A fixed cap of 8 (2 per worker + 4) made 32 streaming clients free and grow a builder for
// most replies: munmap's TLB shootdowns, page faults and the builder's doubling copies doubled
// the server's CPU per pose (0.87 against 0.41 ms at 8 clients, bench/server_bench).
//
// take():                  a cleared builder, reused or new (1 KiB to start).
// give_back(builder):      keeps it for the next take() while fewer than the cap are idle and
//                          its reply was at most kLargestKeptBytes (a 72k pose with normals
//                          is 1.7 MB; a map or sheet's builder is freed).
// set_connections(count):  the open connections the cap allows for; frees idle ones above it.
// Used on the server's I/O thread only (not thread-safe).
#pragma once

#include <flatbuffers/flatbuffers.h>

#include <cstddef>
#include <vector>

namespace sweepd::server {

class ReplyBuilderPool {
 public:
  static constexpr std::size_t kLargestKeptBytes = 8u << 20;
  explicit ReplyBuilderPool(std::size_t base) : base_(base) {}

  flatbuffers::FlatBufferBuilder take();
  void give_back(flatbuffers::FlatBufferBuilder builder);
  void set_connections(std::size_t count);

  std::size_t idle() const { return idle_.size(); }

 private:
  std::size_t cap() const { return base_ + connections_; }

  std::size_t base_;
  std::size_t connections_ = 0;
  std::vector<flatbuffers::FlatBufferBuilder> idle_;
};

}  // namespace sweepd::server
