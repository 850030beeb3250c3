// read_pose_message: a Pose, or the pose of a PositionMapRequest (`map` set), turned into the
// PoseRequest a worker deforms (pose_request.h), or the RequestError to answer instead:
// UnknownModel (no model with the pose's id), the pose's own problem (read_pose_request; it
// counts against the model), or an InvalidArgument position map request
// (check_position_map_request). Runs on the I/O thread; the request's `received` is left for
// the caller to stamp.
#pragma once

#include <cstdint>
#include <variant>

#include "protocol/sweepd_generated.h"
#include "server/handlers/pose_request.h"
#include "server/handlers/request_error.h"
#include "server/models/model_service.h"

namespace sweepd::server {

std::variant<PoseRequest, RequestError> read_pose_message(
    const ModelService& models, const protocol::Pose& pose, std::uint64_t request_id,
    const protocol::PositionMapRequest* map = nullptr);

}  // namespace sweepd::server
