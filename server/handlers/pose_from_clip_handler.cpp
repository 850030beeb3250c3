#include "server/handlers/pose_from_clip_handler.h"

#include "server/handlers/pose_intake.h"

namespace sweepd::server {

namespace pb = sweepd::protocol;

void handle_pose_from_clip(const pb::Message& message, RequestSession& session) {
  const std::uint64_t request_id = message.request_id();
  const pb::PoseFromClip* request = message.body_as_PoseFromClip();
  if (request->pose() == nullptr || request->clip() == nullptr) {
    session.send_error({pb::ErrorCode::InvalidArgument, "a PoseFromClip needs a pose and a clip"},
                       request_id);
    return;
  }
  ConnectionEnvironment& environment = session.environment();
  session.queue_pose(read_clip_pose_message(environment.models, environment.clips, *request->pose(),
                                            *request->clip(), request_id),
                     request_id);
}

}  // namespace sweepd::server
