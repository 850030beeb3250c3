// Pose intake: a pose-carrying message turned into the PoseRequest a worker deforms
// (pose_request.h), or the RequestError to answer instead. Runs on the I/O thread; the
// request's `received` is left for the caller to stamp.
//
// read_pose_message: a Pose, or the pose of a PositionMapRequest (`map` set): UnknownModel (no
//   model with the pose's id), the pose's own problem (read_pose_request; it counts against the
//   model), or an InvalidArgument position map request (check_position_map_request).
// read_clip_pose_message (1.4): a PoseFromClip, or a PositionMapRequest with a clip (`map`
//   set): the pose is that clip frame played on the model (HeldClip::player: retargeted, or an
//   own_skeleton glTF clip joint for joint; motion::sample_clip), and `pose` gives only the model,
//   method, features and output. Beyond read_pose_message's errors: UnknownClip (no clip with that
//   id: upload it again), InvalidArgument for a pose carrying rotations or a root translation, a
//   frame out of range, a time that is NaN, infinite or out of range, or a clip that cannot drive
//   the model.
// read_named_pose_message (1.4): a PoseByName: rotations keyed by joint name, mapped onto the
//   model's joints (motion::named_joints), the others at rest. Beyond read_pose_message's
//   errors: InvalidArgument for names and rotations of different counts, or names matching no
//   joint (all named in the message).
#pragma once

#include <cstdint>
#include <variant>

#include "protocol/sweepd_generated.h"
#include "server/handlers/pose_request.h"
#include "server/handlers/request_error.h"
#include "server/models/clip_store.h"
#include "server/models/model_lookup.h"

namespace sweepd::server {

std::variant<PoseRequest, RequestError> read_pose_message(
    const ModelLookup& models, const protocol::Pose& pose, std::uint64_t request_id,
    const protocol::PositionMapRequest* map = nullptr);

std::variant<PoseRequest, RequestError> read_clip_pose_message(
    const ModelLookup& models, const ClipStore& clips, const protocol::Pose& pose,
    const protocol::ClipFrame& clip, std::uint64_t request_id,
    const protocol::PositionMapRequest* map = nullptr);

std::variant<PoseRequest, RequestError> read_named_pose_message(const ModelLookup& models,
                                                                const protocol::PoseByName& named,
                                                                std::uint64_t request_id);

}  // namespace sweepd::server
