#include "server/handlers/subscribe_stream_handler.h"

#include <string>

#include "server/handlers/reply_size.h"
#include "server/handlers/work_size.h"
#include "server/log_event.h"
#include "server/replies/stream_subscribed.h"
#include "server/services/vmc/vmc_receivers.h"

namespace sweepd::server {

namespace pb = sweepd::protocol;

void handle_subscribe_stream(const pb::Message& message, RequestSession& session) {
  const std::uint64_t request_id = message.request_id();
  const pb::SubscribeStream* request = message.body_as_SubscribeStream();
  const auto refuse = [&](pb::ErrorCode code, const std::string& why) {
    session.send_error({code, "SubscribeStream: " + why}, request_id);
  };
  const VmcReceivers* receivers = session.environment().vmc;
  if (receivers == nullptr) {
    refuse(pb::ErrorCode::NotAvailable,
           "this server receives no stream (start it with --vmc-listen ADDR[:PORT][=MODEL])");
    return;
  }
  const std::string name = request->stream() ? request->stream()->str() : "";
  VmcReceiver* receiver = receivers->find(name);
  if (receiver == nullptr) {
    refuse(pb::ErrorCode::InvalidArgument, "no stream named '" + name +
                                               "' (this server's streams: " +
                                               receivers->stream_names() + ")");
    return;
  }
  if (session.delivery() != pb::PoseDelivery::LatestWins) {
    refuse(pb::ErrorCode::InvalidArgument,
           "a stream is sent latest wins: say delivery LatestWins in Hello");
    return;
  }
  const pb::Pose* pose = request->pose();
  if (pose == nullptr) {
    refuse(pb::ErrorCode::InvalidArgument, "needs a pose (its method, features and output)");
    return;
  }
  if ((pose->rotations() != nullptr && pose->rotations()->size() > 0) ||
      pose->root_translation() != nullptr) {
    refuse(pb::ErrorCode::InvalidArgument,
           "the pose carries no rotations or root translation (the stream gives them)");
    return;
  }
  const ModelHandle model = receiver->model();
  if (!model) {
    refuse(pb::ErrorCode::UnknownModel, "the stream '" + name + "' poses the model '" + name +
                                            "', which this server does not hold: load it");
    return;
  }
  // The request as every frame will be: the pose's method, features and output, checked once.
  PoseRequest frame_request;
  if (auto problem = read_posed_request(*pose, deform::rest_pose(model->bound.model.skeleton),
                                        model, request_id, frame_request)) {
    refuse(problem->code, problem->message);
    return;
  }
  // Every frame's reply has this size: refused now, not once per frame.
  if (auto too_large =
          check_reply_fits(frame_request, session.environment().config.max_frame_bytes)) {
    refuse(too_large->code, too_large->message);
    return;
  }
  // Each frame's working memory comes from this client's share (Connection::queue_pose): a
  // subscription no frame of which could ever fit is refused now, not once per frame.
  if (const std::optional<WorkRefusal> never =
          session.environment().work_budget.refusal_whatever_is_held(
              pose_work_bytes(frame_request))) {
    refuse(pb::ErrorCode::ResourceExhausted,
           "each frame " + describe(*never) +
               "; ask for Float32 vertices (deformed straight into the reply) or no normals");
    return;
  }
  flatbuffers::FlatBufferBuilder builder = session.take_builder();
  build_stream_subscribed(builder, name, model->id, request_id);
  session.send(std::move(builder));
  log_event("stream_subscribed", {{"connection", session.connection_id()}, {"stream", name}});
  receiver->subscribe(
      [weak = session.weak_session(), frame_request, request_id](
          const ModelHandle& posed_model, const deform::Pose& frame_pose, std::uint64_t frame,
          std::chrono::steady_clock::time_point arrived) {
        const std::shared_ptr<RequestSession> subscriber = weak.lock();
        // Gone, or closing: a frame queued now would keep a draining connection open.
        if (!subscriber || subscriber->draining()) return false;
        PoseRequest request = frame_request;
        request.model = posed_model;
        request.pose = frame_pose;
        request.sequence = frame;
        request.received = arrived;
        if (const deform::JobProblem problem = request.job(0, {}, {}).validate()) {
          subscriber->queue_pose(
              RequestError{pb::ErrorCode::InvalidPose,
                           "stream frame " + std::to_string(frame) + " for model " +
                               std::to_string(posed_model->id) + ": " + problem.message,
                           frame, posed_model->id},
              request_id);
        } else {
          subscriber->queue_pose(std::move(request), request_id);
        }
        return true;
      });
}

}  // namespace sweepd::server
