// ConnectionEnvironment: what the server lends every connection — its configuration, the
// services requests use (models, clips, collision, position maps, contact sheets, the VMC
// stream), the pools work runs on, the buffer budget, the work budget and reply builders shared
// by all clients,
// the failed authentications of each address and the count of authenticated connections, and
// the counters Stats and /metrics read. Owned by Server; a connection and its request handlers
// (server/handlers/) reach it by reference, on the I/O thread unless a field says otherwise.
#pragma once

#include <asio.hpp>
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <vector>

#include "protocol/framing.h"
#include "server/config.h"
#include "server/models/clip_store.h"
#include "server/models/model_service.h"
#include "server/services/collision_service.h"
#include "server/services/contact_sheet_service.h"
#include "server/services/position_map_service.h"
#include "server/services/vmc/vmc_receivers.h"
#include "server/services/work_budget.h"
#include "server/transport/auth_backoff.h"
#include "server/transport/connection_counters.h"
#include "server/transport/fair_work_queue.h"
#include "server/transport/reply_builder_pool.h"
#include "server/transport/traffic_counters.h"

namespace sweepd::server {

struct ConnectionEnvironment {
  const ServerConfig& config;
  ModelService& models;
  FairWorkQueue& workers;          // poses, maps, loads and uploads, fair between connections
  SpareCores& spare_cores;         // the workers' cores no job holds (deform_threads 0)
  asio::thread_pool& gpu_waiters;  // poses whose pair detection waits on the GPU thread
  PositionMapService& position_maps;
  ContactSheetService& contact_sheets;  // ContactSheetRequest (1.11)
  ClipStore& clips;                     // UploadClip's clips (1.4)
  CollisionService& collision;
  std::chrono::steady_clock::time_point started;
  std::function<void(std::uint64_t connection_id)> on_close;
  std::function<std::vector<ConnectionCounters>()> all_counters;
  std::map<std::uint32_t, ModelCounters> model_counters;
  protocol::BufferBudget& buffer_budget;  // frames being read and replies waiting, all clients
  WorkBudget& work_budget;                // requests' working memory, all clients (any thread)
  ReplyBuilderPool& builders;             // idle reply builders, all clients
  TrafficCounters traffic;                // requests, errors and latencies of every connection
  AuthBackoff& auth_backoff;              // failed authentications per peer address
  std::size_t members_open = 0;           // authenticated connections (max_connections)
  VmcReceivers* vmc = nullptr;            // the VMC streams (--vmc-listen); null: none received
};

}  // namespace sweepd::server
