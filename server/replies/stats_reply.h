// build_stats: the Stats reply to StatsRequest — the server's uptime, per loaded model its
// poses, errors and deformation latency percentiles (model_counters; a model with no entry
// reports zeros), per open connection its counters and latency percentiles, and the collision
// backend with its fallbacks and per-stage times (CollisionSnapshot, Stats.collision). Finishes
// `builder` as one frame carrying `request_id`.
#pragma once

#include <cstdint>
#include <map>
#include <span>

#include "protocol/sweepd_generated.h"
#include "server/models/model_registry.h"
#include "server/services/collision_service.h"
#include "server/transport/connection_counters.h"

namespace sweepd::server {

void build_stats(flatbuffers::FlatBufferBuilder& builder, std::uint64_t uptime_ns,
                 std::span<const ModelHandle> models,
                 const std::map<std::uint32_t, ModelCounters>& model_counters,
                 std::span<const ConnectionCounters> connections,
                 const CollisionSnapshot& collision, std::uint64_t request_id);

}  // namespace sweepd::server
