// ServerSnapshot: a copy of the Server's counters and gauges taken on its I/O thread
// (Server::snapshot), so the HTTP side port's thread can format /metrics without touching
// state the I/O thread owns.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "server/services/collision_service.h"
#include "server/services/vmc/vmc_receivers.h"
#include "server/transport/traffic_counters.h"

namespace sweepd::server {

struct ModelSnapshot {
  std::uint32_t id = 0;
  std::string name;
  std::uint64_t poses = 0, errors = 0;
};

struct ServerSnapshot {
  TrafficCounters traffic;
  ConnectionTotals all_connections;        // closed and open together
  std::uint64_t connections_accepted = 0;  // admitted or refused, since start
  std::uint64_t connections_open = 0;
  std::uint64_t strangers_open = 0;  // of those, not authenticated (nor cut) yet
  // Of those, on the WebSocket listener (--ws-listen).
  std::uint64_t websocket_connections_accepted = 0, websocket_connections_open = 0;
  std::uint64_t poses_waiting = 0;  // queued behind a running pose, all connections
  std::uint64_t poses_running = 0;
  std::uint64_t buffered_bytes = 0;  // frames being read and replies waiting (BufferBudget)
  std::uint64_t work_bytes = 0;         // requests' working memory reserved now (WorkBudget)
  std::uint64_t work_budget_bytes = 0;  // its limit, --work-budget-bytes
  std::uint64_t work_refusals = 0;      // requests refused for it
  std::uint64_t store_bytes = 0;     // the store directory's files (ModelService::store_bytes)
  std::vector<ModelSnapshot> models;
  CollisionSnapshot collision;  // the collision backend and its GPU fallbacks
  std::vector<VmcSnapshot> vmc;  // each VMC receiver's counters (--vmc-listen); none: off
};

}  // namespace sweepd::server
