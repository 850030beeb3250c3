// TrafficCounters: what the whole server has seen since it started, for /metrics — requests
// by message type, errors by code, pose and position-map latency histograms, failed
// authentications and shed strangers, and the sums of
// the connections already closed (the open ones keep theirs in ConnectionCounters, so a total
// is closed + open). Kept on the I/O thread only, like ConnectionCounters; the HTTP side port
// reads a copy (ServerSnapshot).
// Arrays are indexed by protocol::Body and protocol::ErrorCode; a body type beyond the
// schema (a newer peer) is counted under Body::NONE.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "protocol/sweepd_generated.h"
#include "server/latency_histogram.h"
#include "server/transport/connection_counters.h"

namespace sweepd::server {

inline constexpr std::size_t kBodyTypes = static_cast<std::size_t>(protocol::Body::MAX) + 1;
inline constexpr std::size_t kErrorCodes = static_cast<std::size_t>(protocol::ErrorCode::MAX) + 1;

struct ConnectionTotals {
  std::uint64_t poses_received = 0, poses_answered = 0, poses_dropped = 0, errors = 0;
  std::uint64_t bytes_in = 0, bytes_out = 0;

  void add(const ConnectionCounters& c) {
    poses_received += c.poses_received;
    poses_answered += c.poses_answered;
    poses_dropped += c.poses_dropped;
    errors += c.errors;
    bytes_in += c.bytes_in;
    bytes_out += c.bytes_out;
  }
};

struct TrafficCounters {
  std::array<std::uint64_t, kBodyTypes> requests{};
  std::array<std::uint64_t, kErrorCodes> errors{};
  LatencyHistogram pose_latency;          // frame read → reply queued, plain poses
  LatencyHistogram position_map_latency;  // the same for PositionMapRequest
  ConnectionTotals closed_connections;
  // Issue 49 item 1: tokens compared and wrong, Hellos refused unchecked while their address
  // waited (AuthBackoff), and strangers shed for a newer one (StrangerSlots).
  std::uint64_t auth_failures = 0, auth_backoff_refusals = 0, strangers_shed = 0;

  void count_request(protocol::Body type) {
    const auto index = static_cast<std::size_t>(type);
    ++requests[index < kBodyTypes ? index : 0];
  }
  void count_error(protocol::ErrorCode code) {
    const auto index = static_cast<std::size_t>(code);
    if (index < kErrorCodes) ++errors[index];
  }
};

}  // namespace sweepd::server
