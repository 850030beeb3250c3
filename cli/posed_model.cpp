#include "cli/posed_model.h"

#include <cstring>
#include <stdexcept>

#include "cli/model_loading.h"
#include "cli/text_format.h"
#include "deform/binding/bind.h"
#include "io/bvh_load.h"
#include "io/joint_name_map_json.h"
#include "io/pose_json.h"
#include "io/sweepbind.h"

namespace sweepd::cli {

const char* const kPosingUsage =
    "  MODEL              a rigged .glb/.gltf (bound on the spot) or a .sweepbind file\n"
    "  --rig RIG.json     rig map override when binding a glTF\n"
    "  --bvh CLIP         a BVH clip, retargeted onto the model by joint names and roles\n"
    "  --bvh-map MAP.json BVH joint name -> model joint name, for rigs the names do not match\n"
    "  --frame N          the clip frame (default 0)\n"
    "  --pose POSE.json   a hand-written pose (format in io/pose_json.h) instead of a clip\n"
    "  --method M         sweep (default), lbs or dqs\n"
    "  --features LIST    with sweep: any of folding,protrusion (collision, paper 4.3),\n"
    "                     volume (preservation, 4.4), bulge (biceps, 4.3)\n";

std::string take_posing_arguments(std::vector<std::string>& args, PosingArguments& out) {
  std::vector<std::string> rest;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    const bool has_value = i + 1 < args.size();
    if (arg == "--rig" && has_value) {
      out.rig = args[++i];
    } else if (arg == "--bvh" && has_value) {
      out.bvh = args[++i];
    } else if (arg == "--bvh-map" && has_value) {
      out.bvh_map = args[++i];
    } else if (arg == "--pose" && has_value) {
      out.pose_file = args[++i];
    } else if (arg == "--frame" && has_value) {
      if (!parse_int(args[++i], 0, 1 << 30, out.frames.first))
        return "--frame expects a frame number >= 0, got '" + args[i] + "'";
      out.frames.last = out.frames.first;
    } else if (arg == "--frames" && has_value) {
      const std::optional<motion::FrameRange> range = motion::parse_frame_range(args[++i]);
      if (!range) return "--frames expects A-B with 0 <= A <= B, got '" + args[i] + "'";
      out.frames = *range;
      out.frame_range = true;
    } else if (arg == "--features" && has_value) {
      std::string list = args[++i] + ",";
      for (std::size_t start = 0, comma; (comma = list.find(',', start)) != std::string::npos;
           start = comma + 1) {
        const std::string feature = list.substr(start, comma - start);
        if (feature == "folding")
          out.features.folding = true;
        else if (feature == "protrusion")
          out.features.protrusion = true;
        else if (feature == "volume")
          out.features.volume = true;
        else if (feature == "bulge")
          out.features.bulge = true;
        else
          return "--features expects folding, protrusion, volume and/or bulge, got '" + feature +
                 "'";
      }
    } else if (arg == "--method" && has_value) {
      const auto method = deform::parse_deform_method(args[++i]);
      if (!method) return "--method expects sweep, lbs or dqs, got '" + args[i] + "'";
      out.method = *method;
    } else if (!arg.starts_with("-") && out.model.empty()) {
      out.model = arg;
    } else {
      rest.push_back(arg);
    }
  }
  args = std::move(rest);
  if (out.model.empty()) return "missing MODEL";
  if (!out.bvh.empty() && !out.pose_file.empty()) return "give --bvh or --pose, not both";
  if (out.bvh.empty() && (out.frame_range || out.frames.first != 0))
    return "--frame/--frames need --bvh";
  if (out.features.any() && out.method != deform::DeformMethod::kSweep)
    return "--features apply to --method sweep";
  return {};
}

motion::JointNameMap load_joint_name_map(const std::filesystem::path& file) {
  return file.empty() ? motion::JointNameMap{} : io::load_joint_name_map_json(file);
}

void require_clip_frames(const PosingArguments& arguments, int frame_count) {
  if (const std::string problem = motion::frame_range_problem(arguments.frames, frame_count);
      !problem.empty())
    throw std::invalid_argument(arguments.bvh.string() + ": " + problem);
}

PosedModel::PosedModel(const PosingArguments& arguments) : arguments_(arguments) {
  if (arguments.model.extension() == ".sweepbind") {
    bound_ = std::make_unique<deform::BoundModel>(io::load_sweepbind(arguments.model));
  } else {
    const LoadedModel loaded = load_model_and_rig(arguments.model, arguments.rig);
    bound_ = std::make_unique<deform::BoundModel>(deform::bind(loaded.model, loaded.rig));
  }
  runtime_ = std::make_unique<deform::ModelRuntime>(*bound_);
  if (!arguments.bvh.empty()) {
    retargeter_.emplace(io::load_bvh(arguments.bvh), bound_->model,
                        load_joint_name_map(arguments.bvh_map));
    require_clip_frames(arguments, retargeter_->frame_count());
  }
  if (!arguments.pose_file.empty())
    file_pose_ = io::load_pose_json(arguments.pose_file, bound_->model.skeleton);
}

deform::Pose PosedModel::pose(int frame) const {
  if (retargeter_) return retargeter_->pose_at_frame(frame);
  if (file_pose_) return *file_pose_;
  return deform::rest_pose(bound_->model.skeleton);
}

void PosedModel::deform(int frame, std::vector<glm::vec3>& positions,
                        std::vector<glm::vec3>& normals) {
  positions.resize(model().vertex_count());
  normals.resize(model().vertex_count());
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
  feature_report_ = job.run(context_).features;
}

std::uint64_t pose_hash(const deform::Pose& pose) {
  std::uint64_t hash = 0xcbf29ce484222325ull;
  auto mix = [&](const void* data, std::size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) hash = (hash ^ bytes[i]) * 0x100000001b3ull;
  };
  mix(pose.local_rotations.data(), pose.local_rotations.size() * sizeof(glm::quat));
  mix(&pose.root_translation, sizeof(pose.root_translation));
  return hash;
}

}  // namespace sweepd::cli
