// What sweepctl's posing commands (pose, render, positionmap) share: a bound model from a
// .glb/.gltf (bound on the spot) or a .sweepbind file, the pose source (a BVH clip retargeted
// onto it, a pose JSON file, or the rest pose), and the deformation method.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "deform/binding/bound_model.h"
#include "deform/job/anatomical_features.h"
#include "deform/job/deform_job.h"
#include "motion/frame_range.h"
#include "motion/retarget.h"

namespace sweepd::cli {

struct PosingArguments {
  std::filesystem::path model;      // .glb/.gltf/.sweepbind
  std::filesystem::path rig;        // optional rig map JSON (binding a glTF)
  std::filesystem::path bvh;        // optional clip
  std::filesystem::path bvh_map;    // optional BVH→model joint name map JSON
  std::filesystem::path pose_file;  // optional pose JSON
  motion::FrameRange frames;        // --frame N or --frames A-B (clip frames)
  bool frame_range = false;         // --frames given: a folder of frames
  deform::DeformMethod method = deform::DeformMethod::kSweep;
  // --features: anatomical features on top of the sweep method (paper §4.3, §4.4).
  deform::AnatomicalFeatures features;
};

// Takes the options it knows out of args (leaving the rest in order). Returns "" or the
// reason the arguments are unusable.
std::string take_posing_arguments(std::vector<std::string>& args, PosingArguments& out);
extern const char* const kPosingUsage;

// The --bvh-map file's joint name map (io/joint_name_map_json.h); empty when no file is given.
motion::JointNameMap load_joint_name_map(const std::filesystem::path& file);
// Throws std::invalid_argument naming the clip when the arguments' frames lie past its end.
void require_clip_frames(const PosingArguments& arguments, int frame_count);

class PosedModel {
 public:
  // Loads, binds (for glTF) and prepares the pose source. Throws with a clear reason.
  explicit PosedModel(const PosingArguments& arguments);
  const deform::Model& model() const { return bound_->model; }
  const deform::BoundModel& bound() const { return *bound_; }
  const PosingArguments& arguments() const { return arguments_; }
  // The pose of clip frame `frame` (or the pose file / rest pose without a clip).
  deform::Pose pose(int frame) const;
  // Deforms into positions and normals (vertex_count() each), features included: one
  // deform::DeformJob. A clip's frame range is a stream (I_C from the previous frame,
  // VolumeChangeSource::kPreviousFrame); a single frame stands alone (kFixedPoint).
  void deform(int frame, std::vector<glm::vec3>& positions, std::vector<glm::vec3>& normals);
  // What folding and protrusion did in the last deform (zeros without them).
  const deform::FeatureReport& feature_report() const { return feature_report_; }

 private:
  PosingArguments arguments_;
  std::unique_ptr<deform::BoundModel> bound_;
  std::unique_ptr<deform::ModelRuntime> runtime_;
  deform::DeformContext context_;
  std::optional<motion::Retargeter> retargeter_;
  std::optional<deform::Pose> file_pose_;
  deform::FeatureReport feature_report_;
};

// A stable 64-bit hash (FNV-1a) of a pose's numbers: names a frame's pose in EXR headers.
std::uint64_t pose_hash(const deform::Pose& pose);

}  // namespace sweepd::cli
