// What the Stats reply reports: per connection (kept by its Connection) and per model (kept by
// the server), touched on the I/O thread only.
#pragma once

#include <cstdint>
#include <string>

#include "server/latency_samples.h"

namespace sweepd::server {

struct ConnectionCounters {
  std::uint64_t connection_id = 0;
  std::string peer, client_name;
  std::uint64_t poses_received = 0, poses_answered = 0, poses_dropped = 0, errors = 0;
  std::uint64_t bytes_in = 0, bytes_out = 0;
  LatencySamples latency;  // frame read → reply queued, recent poses
};

struct ModelCounters {
  std::uint64_t poses = 0, errors = 0;
  LatencySamples deform_latency;
};

}  // namespace sweepd::server
