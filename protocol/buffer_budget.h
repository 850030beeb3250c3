// BufferBudget: one limit on the bytes many connections buffer together — incoming frames
// being stored (protocol::FrameReader asks before its storage grows) and replies waiting to
// be written — so that many clients, honest or not, cannot together take more memory than an
// operator allowed. Thread-safe (atomic); never blocks.
//
// take(n):        takes n bytes if used() + n stays within limit(); false (nothing taken)
//                 otherwise.
// take_anyway(n): takes n bytes whatever the limit (memory already in use, e.g. a reply that
//                 is built); used() may pass limit() until they are given back.
// give_back(n):   returns n bytes taken earlier.
#pragma once

#include <atomic>
#include <cstddef>

namespace sweepd::protocol {

class BufferBudget {
 public:
  explicit BufferBudget(std::size_t limit_bytes) : limit_(limit_bytes) {}

  bool take(std::size_t bytes);
  void take_anyway(std::size_t bytes) { used_.fetch_add(bytes); }
  void give_back(std::size_t bytes) { used_.fetch_sub(bytes); }

  std::size_t used() const { return used_.load(); }
  std::size_t limit() const { return limit_; }

 private:
  const std::size_t limit_;
  std::atomic<std::size_t> used_{0};
};

}  // namespace sweepd::protocol
