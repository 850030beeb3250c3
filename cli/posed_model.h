// PosedModel: what sweepctl's posing commands (pose, render, positionmap, metrics, check, sheet)
// deform here — a bound model from a .glb/.gltf (bound on the spot as sweepctl bind binds it:
// adapted) or a .sweepbind file, posed from their PosingArguments (cli/posing_arguments.h) with
// its deformation method; folding's pairs come from the --collision backend
// (cli/local_collision.h). Its clip is a BVH or --clip-from's
// glTF animation retargeted (motion::Retargeter), or --clip's animation of the model's own
// file played joint for joint (motion::OwnSkeletonClip); frames and times are sampled through
// motion::sample_clip.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "cli/local_collision.h"
#include "cli/posing_arguments.h"
#include "deform/binding/bound_model.h"
#include "deform/job/deform_job.h"
#include "motion/clip_poses.h"
#include "motion/joint_name_map.h"

namespace sweepd::cli {

// The --bvh-map file's joint name map (io/json/joint_name_map_json.h); empty when no file is given.
motion::JointNameMap load_joint_name_map(const std::filesystem::path& file);
// Throws std::invalid_argument naming the clip when the arguments' frames lie past its end.
void require_clip_frames(const PosingArguments& arguments, int frame_count);
// The clip's frames as the arguments count them: at --fps (the clip's duration resampled), else
// the clip's own.
int clip_frame_count(const PosingArguments& arguments, const motion::ClipPoses& clip);
// The model posed as the arguments' frame of the clip: at --time, at frame / --fps seconds, or
// the clip's own frame (motion::sample_clip; std::invalid_argument outside the clip).
deform::Pose clip_pose(const PosingArguments& arguments, const motion::ClipPoses& clip, int frame);
// The arguments' clip played on `model` (read from the arguments' MODEL file): --bvh or
// --clip-from's animation retargeted (motion::Retargeter, with --bvh-map), or --clip's animation
// of MODEL's own file joint for joint (motion::OwnSkeletonClip; MODEL must be a glTF, FBX or
// COLLADA file);
// null without a clip. Prints the player's warnings (joints left unmapped on either side) to
// stderr, naming the clip's file. Throws naming the file and the problem.
std::unique_ptr<motion::ClipPoses> clip_player(const PosingArguments& arguments,
                                               const deform::Model& model);

class PosedModel {
 public:
  // Loads, binds (for glTF) and prepares the pose source. Throws with a clear reason.
  explicit PosedModel(const PosingArguments& arguments);
  const deform::Model& model() const { return bound_->model; }
  const deform::BoundModel& bound() const { return *bound_; }
  const deform::ModelRuntime& runtime() const { return *runtime_; }
  const PosingArguments& arguments() const { return arguments_; }
  // The pose of clip frame `frame` (or the pose file / rest pose without a clip).
  deform::Pose pose(int frame) const;
  // The clip's frame count (clip_frame_count); 1 without a clip.
  int frame_count() const;
  // The clip's own frame rate (its file's); 0 without a clip.
  float clip_frames_per_second() const {
    return clip_ ? clip_->motion().frames_per_second() : 0.0f;
  }
  // The clip's player (a Retargeter for --bvh and --clip-from); null without a clip.
  const motion::ClipPoses* clip() const { return clip_.get(); }
  // Deforms into positions and normals (vertex_count() each), features included: one
  // deform::DeformJob. A clip's frame range is a stream (I_C from the previous frame,
  // VolumeChangeSource::kPreviousFrame); a single frame stands alone (kFixedPoint).
  void deform(int frame, std::vector<glm::vec3>& positions, std::vector<glm::vec3>& normals);
  // The same without normals (a point cache holds none; on the 72k mannequin they are about
  // half of a frame's deformation time).
  void deform_positions(int frame, std::vector<glm::vec3>& positions);
  // What folding and protrusion did in the last deform (zeros without them).
  const deform::FeatureReport& feature_report() const { return feature_report_; }
  // The collision backend (--collision) with its stage times over every deform; null when
  // folding and protrusion are not selected (then EGL is not probed).
  const LocalCollision* collision() const { return collision_ ? &*collision_ : nullptr; }

 private:
  // One deform::DeformJob into positions and normals (empty: none).
  void run_job(int frame, std::span<glm::vec3> positions, std::span<glm::vec3> normals);

  PosingArguments arguments_;
  std::unique_ptr<deform::BoundModel> bound_;
  std::unique_ptr<deform::ModelRuntime> runtime_;
  deform::DeformContext context_;
  std::unique_ptr<motion::ClipPoses> clip_;
  std::optional<deform::Pose> file_pose_;
  deform::FeatureReport feature_report_;
  std::optional<LocalCollision> collision_;
};

}  // namespace sweepd::cli
