// RequestSession: what a request handler may ask of the connection its request came on. The
// transport (server/transport/connection.h) implements it; a handler runs on the I/O thread,
// reads its message (valid only until it returns: copy what work on another thread needs) and
// answers through the session, at once or from work run off the I/O thread.
//
// environment(): the server's services, pools, budget and counters.
// send / send_error: queue a reply, or an Error for the request (error.charged_model's count
//   raised in Stats when set); replies are written in the order they are queued.
// queue_pose: a pose checked by the pose intake (server/handlers/pose_intake.h), or its
//   refusal, into the connection's pose queue, which orders, drops (LatestWins) and deforms it.
// run_in_order(pool, work): `work` runs on `pool`; the connection reads no further request
//   until the Reply it returns has run on the I/O thread, so replies stay in request order.
// drain: Bye — finish and answer what was received, then close.
// delivery: the pose delivery the client chose in Hello. weak_session: this session, held
//   weakly, for work that outlives the request (a stream's subscription, 1.15): it locks to
//   null once the connection is gone. draining: Bye, a fatal error or shutdown has begun: the
//   connection takes no new work (a subscription stops queueing frames, so that it closes).
// shared_region / send_region (1.10): the connection's shared memory region, and the reply
//   that carries a newly made one's descriptor (a Unix socket only: unix_socket()).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <variant>

#include "protocol/sweepd_generated.h"
#include "server/handlers/pose_request.h"
#include "server/handlers/request_error.h"
#include "server/transport/connection_environment.h"
#include "server/transport/shared_region.h"

namespace sweepd::server {

class RequestSession {
 public:
  // Where work off the I/O thread runs: the workers, fair between connections, or the pool kept
  // for work that waits on the GPU thread (it must not hold a worker meanwhile).
  enum class Pool { kWorkers, kGpuWaiters };
  // What work hands back to the I/O thread: the reply it sends.
  using Reply = std::function<void(RequestSession& session)>;

  virtual std::uint64_t connection_id() const = 0;
  virtual ConnectionEnvironment& environment() = 0;
  virtual flatbuffers::FlatBufferBuilder take_builder() = 0;
  virtual void send(flatbuffers::FlatBufferBuilder builder) = 0;
  virtual void send_error(const RequestError& error, std::uint64_t request_id) = 0;
  virtual void queue_pose(std::variant<PoseRequest, RequestError> intake,
                          std::uint64_t request_id) = 0;
  virtual void run_in_order(Pool pool, std::function<Reply()> work) = 0;
  virtual void drain() = 0;
  virtual protocol::PoseDelivery delivery() const = 0;
  virtual std::weak_ptr<RequestSession> weak_session() = 0;
  virtual bool draining() const = 0;
  virtual bool unix_socket() = 0;
  virtual const SharedRegion* shared_region() const = 0;
  virtual void send_region(std::shared_ptr<const SharedRegion> region,
                           flatbuffers::FlatBufferBuilder reply) = 0;

 protected:
  ~RequestSession() = default;
};

}  // namespace sweepd::server
