#include <memory>
#include <string>
#include <utility>

#include "server/elapsed_time.h"
#include "server/handlers/reply_size.h"
#include "server/handlers/work_size.h"
#include "server/transport/connection.h"

namespace sweepd::server {

namespace pb = sweepd::protocol;

// Poses run one at a time per connection, in order, on the worker pool (or the GPU waiters').

void Connection::queue_pose(std::variant<PoseRequest, RequestError> intake,
                            std::uint64_t request_id) {
  ++counters_.poses_received;
  // A pose is activity: a stream's subscriber, which sends no request while its frames come
  // (SubscribeStream), is not idle.
  arm_idle_deadline();
  if (const RequestError* error = std::get_if<RequestError>(&intake)) {
    send_error(*error, request_id);
    return;
  }
  PoseRequest& request = std::get<PoseRequest>(intake);
  if (auto error = place_in_shared_region(request, shared_region_)) {
    send_error(*error, request_id);
    return;
  }
  if (auto error = check_reply_fits(request, environment_.config.max_frame_bytes)) {
    send_error(*error, request_id);
    return;
  }
  if (auto error = reserve_pose_work(request, environment_.work_budget, id())) {
    send_error(*error, request_id);
    return;
  }
  // A stream's frame comes with the time its datagram reached the host (VmcReceiver).
  if (request.received == Clock::time_point{}) request.received = Clock::now();
  if (delivery_ == pb::PoseDelivery::LatestWins) {
    // Only plain poses go stale; a requested position map is always rendered.
    const std::size_t dropped = std::erase_if(
        waiting_poses_, [](const PoseRequest& waiting) { return !waiting.position_map; });
    dropped_since_reply_ += static_cast<std::uint32_t>(dropped);
    counters_.poses_dropped += dropped;
  }
  waiting_poses_.push_back(std::move(request));
  start_next_pose();
}

void Connection::start_next_pose() {
  if (pose_running_ || waiting_poses_.empty() || closed_) return;
  if (outgoing_.size() >= environment_.config.max_poses_in_flight) return;  // client not reading
  pose_running_ = true;
  auto request = std::make_shared<PoseRequest>(std::move(waiting_poses_.front()));
  waiting_poses_.pop_front();
  // Drops are reported by the next PosedVertices (a PositionMap has no field for them).
  const std::uint32_t dropped = request->position_map ? 0 : dropped_since_reply_;
  dropped_since_reply_ -= dropped;
  auto builder = std::make_shared<flatbuffers::FlatBufferBuilder>(take_builder());
  // A pose whose folding waits on the GPU thread runs on the pool kept for that, so that its
  // wait never holds a deformation worker another connection's CPU work could use.
  const bool waits_on_gpu = environment_.collision.backend() == gpu::CollisionBackend::kGpu &&
                            request->method == deform::DeformMethod::kSweep &&
                            request->features.collision();
  auto job = [self = shared_from_this(), request, builder, dropped]() {
    std::string failure;
    pb::ErrorCode code = pb::ErrorCode::Internal;
    std::uint64_t deform_ns = 0;
    try {
      // Another replica's edit of the model on a shared store: posed from here on (one stat).
      request->model = self->environment_.models.current(request->model);
      if (request->position_map) {
        deform_ns =
            self->writer_.write_position_map(*request, self->environment_.position_maps, *builder);
      } else {
        deform_ns = self->writer_.write(*request, dropped, *builder);
      }
    } catch (const std::exception& error) {
      code = error_code_of(error);
      failure = error.what();
    }
    std::optional<std::size_t> sent;
    if (failure.empty()) {
      // Set before the client can see the reply: a request other than a pose that it sends
      // after reading it (a Stats) waits until the I/O thread has counted this pose.
      self->reply_uncounted_.store(true, std::memory_order_release);
      sent = self->gate_.try_send({builder->GetBufferPointer(), builder->GetSize()});
      if (!sent) self->reply_uncounted_.store(false, std::memory_order_relaxed);
    }
    asio::post(self->stream_.get_executor(), [self, request, builder, failure, code, dropped,
                                              deform_ns, sent]() {
      self->pose_running_ = false;
      if (failure.empty()) {
        self->count_pose(*request, deform_ns);
        self->reply_uncounted_.store(false, std::memory_order_relaxed);
        self->deliver_pose(std::move(*builder), sent);
      } else {
        ++self->environment_.model_counters[request->model->id].errors;
        self->dropped_since_reply_ += dropped;  // still owed to the next reply
        self->send_error(code, "pose " + std::to_string(request->sequence) + ": " + failure,
                         request->sequence, request->request_id);
      }
      self->start_next_pose();
      self->process_input();
      self->close_if_done();
    });
  };
  if (waits_on_gpu) {
    asio::post(environment_.gpu_waiters, std::move(job));
  } else {
    environment_.workers.post(fair_share_, std::move(job));
  }
}

void Connection::count_pose(const PoseRequest& request, std::uint64_t deform_ns) {
  ++counters_.poses_answered;
  const std::uint64_t latency_ns = nanoseconds_since(request.received);
  counters_.latency.add(latency_ns);
  (request.position_map ? environment_.traffic.position_map_latency
                        : environment_.traffic.pose_latency)
      .add(latency_ns);
  ModelCounters& model = environment_.model_counters[request.model->id];
  ++model.poses;
  model.deform_latency.add(deform_ns);
}

void Connection::deliver_pose(flatbuffers::FlatBufferBuilder builder,
                              std::optional<std::size_t> sent) {
  if (!sent) {
    send(std::move(builder));
    return;
  }
  counters_.bytes_out += *sent;
  if (*sent == builder.GetSize()) {
    environment_.builders.give_back(std::move(builder));
  } else {
    gate_.take_remainder();
    queue_reply(std::move(builder), *sent);
  }
}

}  // namespace sweepd::server
