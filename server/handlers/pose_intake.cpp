#include "server/handlers/pose_intake.h"

#include <string>

#include "server/handlers/position_map_service.h"

namespace sweepd::server {

std::variant<PoseRequest, RequestError> read_pose_message(const ModelService& models,
                                                          const protocol::Pose& pose,
                                                          std::uint64_t request_id,
                                                          const protocol::PositionMapRequest* map) {
  const ModelHandle model = models.find(pose.model_id());
  if (!model) {
    return RequestError{protocol::ErrorCode::UnknownModel,
                        "pose " + std::to_string(pose.sequence()) + ": no model with id " +
                            std::to_string(pose.model_id()),
                        pose.sequence()};
  }
  PoseRequest request;
  if (auto problem = read_pose_request(pose, model, request_id, request)) {
    return RequestError{problem->code, problem->message, pose.sequence(), model->id};
  }
  if (map != nullptr) {
    if (std::string problem = check_position_map_request(*map, model->bound.model);
        !problem.empty()) {
      return RequestError{protocol::ErrorCode::InvalidArgument, std::move(problem),
                          pose.sequence()};
    }
    request.position_map = PositionMapParams{map->width(), map->height(), map->layers(),
                                             map->compression(), map->half_normals()};
  }
  return request;
}

}  // namespace sweepd::server
