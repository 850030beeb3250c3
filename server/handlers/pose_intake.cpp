#include "server/handlers/pose_intake.h"

#include <functional>
#include <string>

#include "motion/clip_sampling.h"
#include "motion/named_joints.h"
#include "server/services/position_map_service.h"

namespace sweepd::server {
namespace {

// The joint rotations and root translation of a request for `model`, or why there are none.
using PoseSource =
    std::function<std::variant<deform::Pose, RequestError>(const ModelHandle& model)>;

std::variant<PoseRequest, RequestError> intake(const ModelLookup& models,
                                               const protocol::Pose& pose, std::uint64_t request_id,
                                               const protocol::PositionMapRequest* map,
                                               const PoseSource& source) {
  const ModelHandle model = models.find(pose.model_id());
  if (!model) {
    return RequestError{protocol::ErrorCode::UnknownModel,
                        "pose " + std::to_string(pose.sequence()) + ": no model with id " +
                            std::to_string(pose.model_id()) + " (" + held_models_clause(models) +
                            ")",
                        pose.sequence()};
  }
  PoseRequest request;
  std::optional<protocol::PoseProblem> problem;
  if (!source) {
    problem = read_pose_request(pose, model, request_id, request);
  } else {
    std::variant<deform::Pose, RequestError> posed = source(model);
    if (RequestError* error = std::get_if<RequestError>(&posed)) {
      error->sequence = pose.sequence();
      return std::move(*error);
    }
    problem = read_posed_request(pose, std::move(std::get<deform::Pose>(posed)), model, request_id,
                                 request);
  }
  if (problem) return RequestError{problem->code, problem->message, pose.sequence(), model->id};
  if (map != nullptr) {
    if (std::string map_problem = check_position_map_request(*map, model->bound.model);
        !map_problem.empty()) {
      return RequestError{protocol::ErrorCode::InvalidArgument, std::move(map_problem),
                          pose.sequence()};
    }
    const bool clip_frame = map->clip() != nullptr && map->clip()->frame().has_value();
    request.position_map =
        PositionMapParams{map->width(),       map->height(),       map->layers(),
                          map->compression(), map->half_normals(),
                          clip_frame ? std::uint64_t{*map->clip()->frame()} : pose.sequence()};
  }
  return request;
}

// "pose 7: " before a reason, as the pose's other errors start.
std::string about(const protocol::Pose& pose, const std::string& reason) {
  return "pose " + std::to_string(pose.sequence()) + ": " + reason;
}

RequestError invalid(const protocol::Pose& pose, const std::string& reason) {
  return RequestError{protocol::ErrorCode::InvalidArgument, about(pose, reason)};
}

}  // namespace

std::variant<PoseRequest, RequestError> read_pose_message(const ModelLookup& models,
                                                          const protocol::Pose& pose,
                                                          std::uint64_t request_id,
                                                          const protocol::PositionMapRequest* map) {
  return intake(models, pose, request_id, map, {});
}

std::variant<PoseRequest, RequestError> read_clip_pose_message(
    const ModelLookup& models, const ClipStore& clips, const protocol::Pose& pose,
    const protocol::ClipFrame& clip, std::uint64_t request_id,
    const protocol::PositionMapRequest* map) {
  const PoseSource from_clip =
      [&](const ModelHandle& model) -> std::variant<deform::Pose, RequestError> {
    if ((pose.rotations() != nullptr && pose.rotations()->size() > 0) ||
        pose.root_translation() != nullptr)
      return invalid(pose,
                     "a clip frame's pose carries no rotations or root translation (the "
                     "clip gives them)");
    const std::string id = clip.clip_id() ? clip.clip_id()->str() : "";
    const ClipHandle held = clips.find(id);
    if (!held)
      return RequestError{protocol::ErrorCode::UnknownClip,
                          about(pose, "no clip with id '" + id + "': upload it (UploadClip)")};
    motion::ClipSample sample;
    if (clip.frame()) sample.frame = *clip.frame();
    if (clip.time_seconds()) sample.seconds = *clip.time_seconds();
    sample.loop = clip.loop();
    sample.frames_per_second = clip.frames_per_second();
    try {
      return motion::sample_clip(*held->player(model), sample);
    } catch (const std::exception& error) {
      return invalid(pose, "clip '" + held->name() + "' on model " + std::to_string(model->id) +
                               ": " + error.what());
    }
  };
  return intake(models, pose, request_id, map, from_clip);
}

std::variant<PoseRequest, RequestError> read_named_pose_message(const ModelLookup& models,
                                                                const protocol::PoseByName& named,
                                                                std::uint64_t request_id) {
  const protocol::Pose& pose = *named.pose();
  const PoseSource by_name =
      [&](const ModelHandle& model) -> std::variant<deform::Pose, RequestError> {
    const std::size_t name_count = named.joint_names() ? named.joint_names()->size() : 0;
    const std::size_t rotation_count = named.rotations() ? named.rotations()->size() : 0;
    if (pose.rotations() != nullptr && pose.rotations()->size() > 0)
      return invalid(pose, "PoseByName's pose carries no rotations (they go with the names)");
    if (name_count != rotation_count)
      return invalid(pose, std::to_string(name_count) + " joint names but " +
                               std::to_string(rotation_count) + " rotations");
    std::vector<std::string> names;
    std::vector<glm::quat> rotations;
    for (std::size_t i = 0; i < name_count; ++i) {
      names.push_back(named.joint_names()->Get(i)->str());
      const protocol::Quat* q = named.rotations()->Get(i);
      rotations.emplace_back(q->w(), q->x(), q->y(), q->z());
    }
    const deform::BoundModel& bound = model->bound;
    try {
      const std::vector<int> joints = motion::named_joints(bound.model.skeleton, bound.rig, names);
      return motion::pose_from_named_rotations(bound.model.skeleton, joints, rotations,
                                               root_translation_of(pose, bound.model.skeleton));
    } catch (const std::invalid_argument& error) {
      return invalid(pose, "model " + std::to_string(model->id) + ": " + error.what());
    }
  };
  return intake(models, pose, request_id, nullptr, by_name);
}

}  // namespace sweepd::server
