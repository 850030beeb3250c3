#include "server/replies/stats_reply.h"

#include <vector>

#include "protocol/messages.h"

namespace sweepd::server {

void build_stats(flatbuffers::FlatBufferBuilder& builder, std::uint64_t uptime_ns,
                 std::span<const ModelHandle> models,
                 const std::map<std::uint32_t, ModelCounters>& model_counters,
                 std::span<const ConnectionCounters> connections,
                 const CollisionSnapshot& collision, std::uint64_t request_id) {
  namespace pb = sweepd::protocol;
  std::vector<flatbuffers::Offset<pb::ConnectionStats>> connection_stats;
  for (const ConnectionCounters& c : connections) {
    const pb::LatencyPercentiles latency = c.latency.percentiles();
    connection_stats.push_back(pb::CreateConnectionStatsDirect(
        builder, c.connection_id, c.peer.c_str(), c.client_name.c_str(), c.poses_received,
        c.poses_answered, c.poses_dropped, c.errors, c.bytes_in, c.bytes_out, &latency));
  }
  const ModelCounters none;
  std::vector<flatbuffers::Offset<pb::ModelStats>> model_stats;
  for (const ModelHandle& model : models) {
    const auto found = model_counters.find(model->id);
    const ModelCounters& counters = found == model_counters.end() ? none : found->second;
    const pb::LatencyPercentiles latency = counters.deform_latency.percentiles();
    model_stats.push_back(pb::CreateModelStatsDirect(builder, model->id, model->name.c_str(),
                                                     counters.poses, counters.errors, &latency));
  }
  const auto collision_stats = pb::CreateCollisionStatsDirect(
      builder, gpu::to_string(collision.backend), collision.reason.c_str(),
      collision.device.c_str(), collision.requests, collision.gpu_fallbacks, collision.detect_ns,
      collision.fold_ns, collision.protrude_ns, collision.upload_ns, collision.readback_ns,
      collision.contact_ns, collision.dispatch_ns);
  pb::finish_message(
      builder,
      pb::CreateStatsDirect(builder, uptime_ns, &model_stats, &connection_stats, collision_stats),
      request_id);
}

}  // namespace sweepd::server
