#include "server/handlers/position_map_request_handler.h"

#include "server/handlers/pose_intake.h"

namespace sweepd::server {

namespace pb = sweepd::protocol;

void handle_position_map_request(const pb::Message& message, RequestSession& session) {
  const std::uint64_t request_id = message.request_id();
  const pb::PositionMapRequest* map = message.body_as_PositionMapRequest();
  if (map->pose() == nullptr) {
    session.send_error({pb::ErrorCode::InvalidArgument, "a PositionMapRequest needs a pose"},
                       request_id);
    return;
  }
  ConnectionEnvironment& environment = session.environment();
  if (map->clip() != nullptr) {
    session.queue_pose(read_clip_pose_message(environment.models, environment.clips, *map->pose(),
                                              *map->clip(), request_id, map),
                       request_id);
  } else {
    session.queue_pose(read_pose_message(environment.models, *map->pose(), request_id, map),
                       request_id);
  }
}

}  // namespace sweepd::server
