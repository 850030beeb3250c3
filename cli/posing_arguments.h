// PosingArguments: what sweepctl's posing commands (pose, render, positionmap, metrics, sheet) read
// from their command line — the model, the pose source (a BVH clip retargeted onto it, a glTF
// animation of the model's own file or retargeted from another glTF, a pose JSON file, or the
// rest pose) and the deformation method — and the flags that fill it, declared here once for
// all of them:
//   add_model_and_clip_flags  MODEL, --rig, --orientation (add_orientation_flag's), --bvh,
//                       --bvh-map, --bvh-up y|z, --feet planted|free (returns --bvh's option);
//                       for commands with frames of their own (sheet)
//   add_posing_flags    those, --clip NAME|INDEX (a glTF animation of MODEL's file, played
//                       joint for joint), --clip-from FILE (--clip's animation, default 0, of
//                       another .glb/.gltf, retargeted like a BVH), --frame, --time T (seconds
//                       into the clip, sampled between frames), --fps F (--frame and --frames
//                       count frames at F per second), --pose, and --frames where the command
//                       takes a frame range (pose, metrics; --frames wins over --frame); --bvh,
//                       --clip and --pose exclude each other, --clip-from excludes --bvh and
//                       --pose, --time excludes --frame and --frames
//   add_method_flags    --method sweep|lbs|dqs, --features LIST and add_collision_flag's
//                       (pose, render, positionmap; metrics has its own --method list)
//   add_method_list_flag  FLAG LIST: comma-separated method names (deform/job/method_choice.h),
//                       `take` gets each one's choice in the order given (metrics, check, sheet)
//   add_collision_flag  --collision auto|gpu|cpu: where folding finds its pairs
//                       (cli/local_collision.h) (through add_method_flags, and metrics)
//   add_orientation_flag  --orientation linear|smooth: the orientation curve Q(t) of a binding
//                       made here (also sweepctl bind's)
//   check_method_flags  the rules CLI11 cannot state: --features need --method sweep,
//                       --collision applies here, not with --server (the daemon's own
//                       --collision decides), --frame, --frames, --time and --fps need a clip
//                       (--bvh, --clip or --clip-from), --bvh-up applies here, not with
//                       --server, and --feet needs a retargeted clip (--bvh or --clip-from),
//                       and --feet free applies here, not with --server (the daemon plants);
//                       throws CLI::ValidationError (call it from the command's callback with
//                       whether --server was given)
// Bad values ("12x", "5-3", an unknown method or feature) are usage errors naming the flag.
#pragma once

#include <CLI/CLI.hpp>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "console/frame_range.h"
#include "deform/job/anatomical_features.h"
#include "deform/job/deform_method.h"
#include "deform/job/method_choice.h"
#include "deform/sweep/orientation_curve.h"
#include "gpu/collision_backend.h"
#include "motion/clip_up_axis.h"
#include "motion/retarget.h"

namespace sweepd::cli {

struct PosingArguments {
  std::filesystem::path model;  // .glb/.gltf/.sweepbind
  std::filesystem::path rig;    // optional rig map JSON (binding a glTF)
  // The orientation curve when binding a glTF (a .sweepbind keeps the one it was bound with).
  deform::OrientationCurveKind orientation = deform::OrientationCurveKind::kLinear;
  std::filesystem::path bvh;        // optional clip
  std::filesystem::path bvh_map;    // optional BVH→model joint name map JSON
  std::string clip;                 // --clip: a glTF animation's name or index
  std::filesystem::path clip_from;  // --clip-from: the glTF file holding --clip (else MODEL)
  std::optional<double> time;       // --time: seconds into the clip
  float fps = 0.0f;                 // --fps: the rate --frame/--frames count at; 0: the clip's
  std::filesystem::path pose_file;  // optional pose JSON
  console::FrameRange frames;       // --frame N or --frames A-B (clip frames)
  bool frame_range = false;         // --frames given: a folder of frames
  // --bvh-up: the clip's up axis (--bvh's); nothing: detected from its skeleton.
  std::optional<motion::UpAxis> bvh_up;
  // --feet: a retargeted clip's feet planted on the floor (default) or left free.
  motion::Feet feet = motion::Feet::kPlanted;
  bool feet_given = false;
  deform::DeformMethod method = deform::DeformMethod::kSweep;
  // --features: anatomical features on top of the sweep method (paper §4.3, §4.4).
  deform::AnatomicalFeatures features;
  // --collision: where folding finds its pairs when it runs here.
  gpu::CollisionChoice collision = gpu::CollisionChoice::kAuto;
  bool collision_given = false;  // --collision was on the command line
  bool frame_given = false;      // --frame or --frames was on the command line

  bool gltf_clip() const { return !clip.empty() || !clip_from.empty(); }
  bool has_clip() const { return !bvh.empty() || gltf_clip(); }
  // The clip's file, for messages: --bvh's, --clip-from's, or MODEL (--clip alone).
  const std::filesystem::path& clip_file() const {
    return !bvh.empty() ? bvh : !clip_from.empty() ? clip_from : model;
  }
};

enum class ClipFrames { kOne, kOneOrRange };  // whether the command takes --frames A-B

CLI::Option* add_model_and_clip_flags(CLI::App& command, PosingArguments& out);
void add_posing_flags(CLI::App& command, PosingArguments& out, ClipFrames frames);
void add_method_flags(CLI::App& command, PosingArguments& out);
CLI::Option* add_method_list_flag(CLI::App& command, const std::string& flag,
                                  const std::function<void(const deform::MethodChoice&)>& take,
                                  const std::string& help);
void add_orientation_flag(CLI::App& command, deform::OrientationCurveKind& out);
void add_collision_flag(CLI::App& command, PosingArguments& out);
void check_method_flags(const PosingArguments& arguments, bool on_server = false);

}  // namespace sweepd::cli
