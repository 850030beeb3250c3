#include "server/handlers/pose_handler.h"

#include "server/handlers/pose_intake.h"

namespace sweepd::server {

namespace pb = sweepd::protocol;

void handle_pose(const pb::Message& message, RequestSession& session) {
  const std::uint64_t request_id = message.request_id();
  session.queue_pose(
      read_pose_message(session.environment().models, *message.body_as_Pose(), request_id),
      request_id);
}

}  // namespace sweepd::server
