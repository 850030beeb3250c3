#include "server/handlers/pose_by_name_handler.h"

#include "server/handlers/pose_intake.h"

namespace sweepd::server {

namespace pb = sweepd::protocol;

void handle_pose_by_name(const pb::Message& message, RequestSession& session) {
  const std::uint64_t request_id = message.request_id();
  const pb::PoseByName* request = message.body_as_PoseByName();
  if (request->pose() == nullptr) {
    session.send_error({pb::ErrorCode::InvalidArgument, "a PoseByName needs a pose"}, request_id);
    return;
  }
  session.queue_pose(read_named_pose_message(session.environment().models, *request, request_id),
                     request_id);
}

}  // namespace sweepd::server
