#include "cli/posed_model.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "cli/model_loading.h"
#include "io/bvh/bvh_load.h"
#include "io/json/joint_name_map_json.h"
#include "io/json/pose_json.h"
#include "io/model_clip_load.h"
#include "io/sweepbind/sweepbind.h"
#include "motion/clip_sampling.h"
#include "motion/own_skeleton_clip.h"
#include "motion/retarget.h"
#include "selfcheck/binding_self_check.h"

namespace sweepd::cli {

motion::JointNameMap load_joint_name_map(const std::filesystem::path& file) {
  return file.empty() ? motion::JointNameMap{} : io::load_joint_name_map_json(file);
}

void require_clip_frames(const PosingArguments& arguments, int frame_count) {
  if (const std::string problem = console::frame_range_problem(arguments.frames, frame_count);
      !problem.empty())
    throw std::invalid_argument(arguments.clip_file().string() + ": " + problem);
}

int clip_frame_count(const PosingArguments& arguments, const motion::ClipPoses& clip) {
  if (arguments.fps <= 0.0f) return clip.frame_count();
  return static_cast<int>(std::floor(clip.duration() * arguments.fps + 1e-6)) + 1;
}

deform::Pose clip_pose(const PosingArguments& arguments, const motion::ClipPoses& clip, int frame) {
  if (arguments.time) return motion::sample_clip(clip, {.seconds = *arguments.time});
  if (arguments.fps > 0.0f)
    return motion::sample_clip(clip, {.seconds = frame / double{arguments.fps}});
  return clip.pose_at_frame(frame);
}

namespace {

// The animation --clip names in `file`, a glTF, FBX or COLLADA file (its first without a name).
motion::Clip file_clip(const std::filesystem::path& file, const std::string& clip) {
  return io::load_model_clip(file, clip.empty() ? "0" : clip);
}

// The player clip_player returns, before its warnings are printed.
std::unique_ptr<motion::ClipPoses> make_clip_player(const PosingArguments& arguments,
                                                    const deform::Model& model) {
  if (!arguments.bvh.empty())
    return std::make_unique<motion::Retargeter>(
        io::load_bvh(arguments.bvh, {.up = arguments.bvh_up}), model,
        load_joint_name_map(arguments.bvh_map), arguments.feet);
  if (!arguments.clip_from.empty())
    return std::make_unique<motion::Retargeter>(file_clip(arguments.clip_from, arguments.clip),
                                                model, load_joint_name_map(arguments.bvh_map),
                                                arguments.feet);
  if (arguments.clip.empty()) return nullptr;
  if (arguments.model.extension() == ".sweepbind")
    throw std::invalid_argument(arguments.model.string() +
                                ": --clip plays an animation of the model's own glTF, FBX or "
                                "COLLADA file, and a .sweepbind holds none; for another file's "
                                "clip give --clip-from FILE");
  return std::make_unique<motion::OwnSkeletonClip>(file_clip(arguments.model, arguments.clip),
                                                   model.skeleton);
}

}  // namespace

std::unique_ptr<motion::ClipPoses> clip_player(const PosingArguments& arguments,
                                               const deform::Model& model) {
  std::unique_ptr<motion::ClipPoses> player = make_clip_player(arguments, model);
  if (player)
    for (const std::string& warning : player->warnings())
      std::fprintf(stderr, "warning: %s: %s\n", arguments.clip_file().string().c_str(),
                   warning.c_str());
  return player;
}

PosedModel::PosedModel(const PosingArguments& arguments) : arguments_(arguments) {
  if (arguments.model.extension() == ".sweepbind") {
    bound_ = std::make_unique<deform::BoundModel>(io::load_sweepbind(arguments.model));
  } else {
    // Bound as sweepctl bind and sweepd bind it: adapted where the self-check finds a refit
    // that wins (selfcheck::adapt_binding), so that check, pose, render and sheet show what
    // a user's .sweepbind and the daemon deform with.
    const LoadedModel loaded = load_model_and_rig(arguments.model, arguments.rig);
    bound_ = std::make_unique<deform::BoundModel>(
        selfcheck::bind_checked(loaded.model, loaded.rig,
                                {.orientation_curve = arguments.orientation}, true)
            .bound);
  }
  runtime_ = std::make_unique<deform::ModelRuntime>(*bound_);
  clip_ = clip_player(arguments, bound_->model);
  if (clip_) require_clip_frames(arguments, frame_count());
  if (!arguments.pose_file.empty())
    file_pose_ = io::load_pose_json(arguments.pose_file, bound_->model.skeleton);
  if (arguments.method == deform::DeformMethod::kSweep && arguments.features.collision())
    collision_.emplace(arguments.collision);
}

deform::Pose PosedModel::pose(int frame) const {
  if (clip_) return clip_pose(arguments_, *clip_, frame);
  if (file_pose_) return *file_pose_;
  return deform::rest_pose(bound_->model.skeleton);
}

int PosedModel::frame_count() const { return clip_ ? clip_frame_count(arguments_, *clip_) : 1; }

void PosedModel::deform(int frame, std::vector<glm::vec3>& positions,
                        std::vector<glm::vec3>& normals) {
  positions.resize(model().vertex_count());
  normals.resize(model().vertex_count());
  run_job(frame, positions, normals);
}

void PosedModel::deform_positions(int frame, std::vector<glm::vec3>& positions) {
  positions.resize(model().vertex_count());
  run_job(frame, positions, {});
}

void PosedModel::run_job(int frame, std::span<glm::vec3> positions, std::span<glm::vec3> normals) {
  deform::Pose p = pose(frame);
  deform::DeformJob job{
      .runtime = *runtime_,
      .pose = p,
      .method = arguments_.method,
      .features = arguments_.features,
      .options = {.volume_change = arguments_.frame_range
                                       ? deform::VolumeChangeSource::kPreviousFrame
                                       : deform::VolumeChangeSource::kFixedPoint},
      .positions = positions,
      .normals = normals};
  if (collision_) job.options.detect = collision_->begin();
  feature_report_ = job.run(context_).features;
  if (collision_) collision_->finish(feature_report_);
}

}  // namespace sweepd::cli
