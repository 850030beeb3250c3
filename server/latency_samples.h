// LatencySamples: the most recent latencies (a ring of kLatencySamples nanosecond values) and
// their percentiles, for Stats — per connection (frame read → reply queued) and per model
// (deformation only).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "protocol/sweepd_generated.h"

namespace sweepd::server {

inline constexpr std::size_t kLatencySamples = 1024;

class LatencySamples {
 public:
  void add(std::uint64_t nanoseconds);
  // p50, p90, p99 (nearest rank below) and max of the samples held; all 0 when empty.
  protocol::LatencyPercentiles percentiles() const;

 private:
  std::vector<std::uint64_t> samples_;
  std::size_t next_ = 0;  // where the next sample goes once the ring is full
};

}  // namespace sweepd::server
