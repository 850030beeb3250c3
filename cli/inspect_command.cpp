// sweepctl inspect FILE: what a model (.glb/.gltf/.fbx/.dae) or motion clip (.bvh) holds, for a
// person; for a model also the detected rig map and what the binding would sweep and skin, and
// for a glTF its animations (duration, frames, channels, joints driven). With --model MODEL
// [--bvh-map MAP] a .bvh clip, or each animation of a model file, is also retargeted onto that
// model (motion::Retargeter, as `pose --bvh` and `--clip-from` do): how its joints were
// matched, and in its warnings the clip joints that drive nothing and the model joints left
// without motion.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "cli/self_check_report.h"
#include "console/text_format.h"
#include "deform/binding/mesh_parts_joined.h"
#include "deform/mesh/mesh_topology.h"
#include "deform/rig/rig_map.h"
#include "io/bvh/bvh_load.h"
#include "io/json/joint_name_map_json.h"
#include "io/model_clip_load.h"
#include "io/model_load.h"
#include "io/sweepbind/sweepbind.h"
#include "motion/clip_up_axis.h"
#include "motion/retarget.h"
#include "selfcheck/binding_self_check.h"

namespace sweepd::cli {

namespace {

// The file's extension in lower case (".glb", ".gltf", ".fbx", ".dae", ".bvh" or another).
std::string file_type(const std::filesystem::path& file) {
  std::string extension = file.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), ::tolower);
  return extension;
}

template <typename Children, typename Label>
void print_tree(const Children& children_of, const Label& label, int node, int depth) {
  std::printf("  %*s%s\n", 2 * depth, "", label(node).c_str());
  for (int child : children_of(node)) print_tree(children_of, label, child, depth + 1);
}

void print_warnings(const std::vector<std::string>& warnings) {
  std::printf("warnings:    %s\n", warnings.empty() ? "none" : "");
  for (const std::string& w : warnings) std::printf("  - %s\n", w.c_str());
}

// The detected rig map: each part's joints and how it was found (name or shape), what the
// binding sweeps and what it leaves to the model's skinning, and the parts not found.
void print_rig(const deform::Skeleton& skeleton) {
  deform::RigMap rig;
  try {
    rig = deform::detect_rig_map(skeleton);
  } catch (const std::invalid_argument& e) {
    std::printf("rig:         refused: %s\n", e.what());
    return;
  }
  std::printf("rig:         detected (each part: [how it was found])\n");
  const std::string listing = deform::describe(rig, skeleton);
  for (std::size_t start = 0; start < listing.size();) {
    const std::size_t end = listing.find('\n', start);
    std::printf("  %s\n", listing.substr(start, end - start).c_str());
    start = end + 1;
  }
  const std::pair<deform::RigPart, bool> parts[] = {
      {deform::RigPart::kLeftArm, !rig.left_arm.absent()},
      {deform::RigPart::kRightArm, !rig.right_arm.absent()},
      {deform::RigPart::kLeftLeg, !rig.left_leg.absent()},
      {deform::RigPart::kRightLeg, !rig.right_leg.absent()}};
  // As the binding plans its sweeps (deform/binding/bind.cpp): a neck of one joint, a torso of
  // one joint with no neck above it and the forearm of an arm without a hand joint are skinned.
  std::vector<std::string> swept;
  std::string skinned;
  if (rig.torso_sweep_chain().size() >= 2)
    swept.push_back(rig.torso.chain.size() >= 2 ? "torso" : "torso (up to the neck's first joint)");
  else
    skinned = "torso (one joint), ";
  if (rig.has_head() && rig.neck.chain.size() >= 2) {
    swept.push_back("neck");
    skinned += "head";
  } else {
    skinned += rig.has_head() ? "neck (one joint) and head" : "neck and head";
  }
  for (const auto& [part, present] : parts) {
    const std::string name = deform::to_string(part);
    if (present) swept.push_back(name);
    const bool arm = part == deform::RigPart::kLeftArm || part == deform::RigPart::kRightArm;
    const deform::ArmJoints& arm_joints =
        part == deform::RigPart::kLeftArm ? rig.left_arm : rig.right_arm;
    const std::string side = name.substr(0, name.find(' '));
    const std::string end = arm && arm_joints.hand < 0 ? side + " forearm and hand"
                                                       : side + (arm ? " hand" : " foot");
    skinned += ", " + (present ? end : name + " (absent)");
  }
  std::string swept_list;
  for (const std::string& part : swept) swept_list += (swept_list.empty() ? "" : ", ") + part;
  std::printf("swept:       %s\n", swept_list.empty() ? "nothing" : swept_list.c_str());
  std::printf("skinned:     %s (with everything below them)\n", skinned.c_str());
}

// Each mesh node of the file: its vertices, primitives, and whether it is skinned and swept
// with the body, skinned by LBS alone (a separate piece), rigid to a joint, or ignored and why.
void print_meshes(const deform::Model& model, const io::LoadReport& report) {
  if (report.meshes.empty()) return;
  std::printf("meshes:      %zu\n", report.meshes.size());
  const std::vector<std::uint8_t> joined = deform::mesh_parts_joined(model);
  for (const io::MeshHandling& mesh : report.meshes) {
    std::string handling = "ignored: " + mesh.ignored;
    int primitives = 0;
    if (mesh.part >= 0) {
      const deform::MeshPart& part = model.parts[mesh.part];
      for (std::size_t k = mesh.part; k < model.parts.size() && model.parts[k].mesh == part.mesh;
           ++k)
        ++primitives;
      handling = part.rigid_joint >= 0
                     ? "rigid to joint " + model.skeleton.joints[part.rigid_joint].name
                 : joined[mesh.part]
                     ? "skinned, swept with the body"
                     : "skinned, LBS only (a separate piece: it shares no position with the body)";
    }
    std::printf("  %s (%zu vertices, %d primitive%s): %s\n", mesh.name.c_str(), mesh.vertex_count,
                primitives, primitives == 1 ? "" : "s", handling.c_str());
  }
}

struct InspectCommandOptions {
  std::filesystem::path file;
  std::filesystem::path model;    // --model: retarget the clip (or the file's animations) onto it
  std::filesystem::path bvh_map;  // --bvh-map: with --model
};

// The model --model names, and the joint name map --bvh-map names (empty without one).
deform::Model target_model(const InspectCommandOptions& options) {
  return options.model.extension() == ".sweepbind" ? io::load_sweepbind(options.model).model
                                                   : io::load_model(options.model);
}
motion::JointNameMap target_name_map(const InspectCommandOptions& options) {
  return options.bvh_map.empty() ? motion::JointNameMap{}
                                 : io::load_joint_name_map_json(options.bvh_map);
}

// `clip` retargeted onto `model` (--model) as posing does: how its joints were matched, in
// words; its warnings (the joints left unmapped on either side) are added to `warnings`.
std::string retargeting(motion::Clip clip, const InspectCommandOptions& options,
                        const deform::Model& model, const motion::JointNameMap& name_map,
                        std::vector<std::string>& warnings) {
  const std::size_t clip_joints = clip.joints.size();
  // Free feet: planting changes no match and no warning, and would pass over every frame.
  const motion::Retargeter retargeter(std::move(clip), model, name_map, motion::Feet::kFree);
  int by_reason[4] = {0, 0, 0, 0};  // in the order of motion::JointMatchReason
  std::size_t undriven = retargeter.unmapped_model_joints().size();
  for (const motion::JointMatch& match : retargeter.matches()) {
    ++by_reason[static_cast<int>(match.reason)];
    undriven += match.driven ? 0 : 1;
  }
  char line[512];
  std::snprintf(line, sizeof line,
                "onto %s (%d joints): %zu of %zu clip joints matched (name map %d, name %d, "
                "role %d, hierarchy %d), %zu unmapped; %zu model joints without motion",
                options.model.string().c_str(), model.skeleton.size(), retargeter.matches().size(),
                clip_joints, by_reason[0], by_reason[1], by_reason[2], by_reason[3],
                retargeter.unmapped_bvh_joints().size(), undriven);
  warnings.insert(warnings.end(), retargeter.warnings().begin(), retargeter.warnings().end());
  return line;
}

// A model file's animations (what `pose --clip NAME|INDEX` plays): each one's duration, frames,
// channels played, the skin joints they drive and their interpolations, or why it cannot play;
// with --model, each retargeted onto that model (as `pose --clip-from`) with its warnings.
void print_animations(const InspectCommandOptions& options) {
  const std::filesystem::path& file = options.file;
  const std::vector<io::FileAnimation> animations = io::load_model_animations(file);
  std::optional<deform::Model> target;
  motion::JointNameMap name_map;
  if (!options.model.empty() && !animations.empty()) {
    target = target_model(options);
    name_map = target_name_map(options);
  }
  std::printf("animations:  %zu%s\n", animations.size(),
              animations.empty() ? "" : " (pose --clip NAME|INDEX)");
  for (std::size_t a = 0; a < animations.size(); ++a) {
    const std::string label = std::to_string(a) + " '" + animations[a].name + "'";
    if (!animations[a].clip) {
      std::printf("  %s: cannot play: %s\n", label.c_str(), animations[a].error.c_str());
      continue;
    }
    const motion::Clip& clip = *animations[a].clip;
    std::vector<bool> driven(clip.joints.size(), false);
    bool kinds[3] = {false, false, false};
    for (const motion::KeyframeTrack& track : clip.tracks) {
      driven[track.joint] = true;
      kinds[static_cast<int>(track.interpolation)] = true;
    }
    // In the order of motion::Interpolation.
    static constexpr const char* kInterpolations[] = {"STEP", "LINEAR", "CUBICSPLINE"};
    std::string interpolations;
    for (int k = 0; k < 3; ++k)
      if (kinds[k])
        interpolations += (interpolations.empty() ? "" : ", ") + std::string(kInterpolations[k]);
    std::printf(
        "  %s: %.3f s, %d frames at %.2f fps, %zu channels played, drives %zu of %zu "
        "joints (%s)\n",
        label.c_str(), clip.duration(), clip.frame_count, clip.frames_per_second(),
        clip.tracks.size(),
        static_cast<std::size_t>(std::count(driven.begin(), driven.end(), true)),
        clip.joints.size(), interpolations.c_str());
    std::vector<std::string> warnings = clip.warnings;
    if (target)
      std::printf("    retargeted %s\n",
                  retargeting(clip, options, *target, name_map, warnings).c_str());
    for (const std::string& warning : warnings) std::printf("    - %s\n", warning.c_str());
  }
}

int inspect_model(const InspectCommandOptions& options) {
  const std::filesystem::path& file = options.file;
  io::LoadReport report;
  const deform::Model model = io::load_model(file, &report);
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (const glm::vec3& p : model.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  int max_influences = 0;
  double influence_sum = 0.0;
  for (const auto& weights : model.skin_weights) {
    const int used = static_cast<int>(
        std::count_if(weights.begin(), weights.end(), [](float w) { return w > 0.0f; }));
    max_influences = std::max(max_influences, used);
    influence_sum += used;
  }
  const deform::MeshTopology topology = deform::analyze_topology(model.positions, model.indices);
  const deform::Skeleton& skeleton = model.skeleton;

  std::printf("file:        %s\n", file.string().c_str());
  std::printf("kind:        skinned model (%s)%s%s\n", report.format.c_str(),
              report.generator.empty() ? "" : ", generator ", report.generator.c_str());
  std::printf("vertices:    %s\n", console::with_thousands(model.vertex_count()).c_str());
  std::printf("triangles:   %s (from %d primitive%s)\n",
              console::with_thousands(model.triangle_count()).c_str(), report.source_primitive_count,
              report.source_primitive_count == 1 ? "" : "s");
  std::printf("joints:      %d\n", skeleton.size());
  std::printf("UVs:         %s\n", model.has_uvs() ? "present" : "absent");
  std::printf("bounds:      min (%.3f, %.3f, %.3f)  max (%.3f, %.3f, %.3f) m\n", lo.x, lo.y, lo.z,
              hi.x, hi.y, hi.z);
  std::printf("height:      %.3f m (Y extent)\n", hi.y - lo.y);
  std::printf("topology:    %s welded positions, %s edges, %zu component%s, %s\n",
              console::with_thousands(topology.welded_vertices).c_str(),
              console::with_thousands(topology.edges).c_str(), topology.components,
              topology.components == 1 ? "" : "s",
              topology.closed_manifold() ? "closed 2-manifold" : "NOT closed 2-manifold");
  if (!topology.closed_manifold())
    std::printf(
        "             %zu boundary edges, %zu non-manifold edges, %zu non-manifold vertices\n",
        topology.boundary_edges, topology.non_manifold_edges, topology.non_manifold_vertices);
  std::printf(
      "weights:     influences per vertex mean %.2f, max %d; %d renormalised, %d unweighted\n",
      influence_sum / std::max<std::size_t>(1, model.vertex_count()), max_influences,
      report.renormalised_weight_count, report.zero_weight_vertex_count);
  print_meshes(model, report);
  print_warnings(report.warnings);
  print_animations(options);
  print_rig(skeleton);
  std::printf("joint tree:\n");
  for (int j = 0; j < skeleton.size(); ++j)
    if (skeleton.joints[j].parent < 0)
      print_tree([&](int n) { return skeleton.children(n); },
                 [&](int n) { return skeleton.joints[n].name; }, j, 0);
  return 0;
}

// A .sweepbind: its model and sweeps, what each sweep was bound with, and the self-check run
// again on the binding as it is (selfcheck/binding_self_check.h).
int inspect_binding(const InspectCommandOptions& options) {
  const deform::BoundModel bound = io::load_sweepbind(options.file);
  std::printf("file:        %s\n", options.file.string().c_str());
  std::printf("kind:        binding (.sweepbind) of '%s'\n", bound.model.name.c_str());
  std::printf("vertices:    %s\n", console::with_thousands(bound.model.vertex_count()).c_str());
  std::printf("joints:      %d\n", bound.model.skeleton.size());
  std::printf("sweeps:      %zu\n", bound.sweeps.size());
  for (const deform::BoundSweep& sweep : bound.sweeps)
    std::printf("  %-10s %zu keys (%d link key%s per link), %s orientation curve, %s\n",
                deform::to_string(sweep.part), sweep.rest_keys.size(), sweep.choice.keys_per_link,
                sweep.choice.keys_per_link == 1 ? "" : "s",
                sweep.choice.orientation_curve == deform::OrientationCurveKind::kSmooth ? "smooth"
                                                                                       : "linear",
                sweep.choice.origin == deform::SweepChoiceOrigin::kSelfCheck
                    ? "chosen by the self-check"
                    : "as the bind options say");
  print_self_check(bound,
                   selfcheck::check_binding(bound, selfcheck::range_of_motion_peaks(bound)));
  return 0;
}

int inspect_motion(const InspectCommandOptions& options) {
  const std::filesystem::path& file = options.file;
  // As the file has it: channels and offsets in its own axes.
  const motion::Clip clip = io::load_bvh(file, {.up = motion::UpAxis::kY});
  const motion::UpAxis up = motion::detect_up_axis(clip);
  std::printf("file:        %s\n", file.string().c_str());
  std::printf("kind:        motion clip (BVH)\n");
  std::printf("up axis:     %s (detected from the skeleton, feet to head%s)\n",
              motion::to_string(up),
              up == motion::UpAxis::kZ ? "; posing turns it Y-up, --bvh-up overrides" : "");
  std::printf("joints:      %zu\n", clip.joints.size());
  std::printf("channels:    %d per frame\n", clip.channel_count);
  std::printf("frames:      %s (header says %s)\n", console::with_thousands(clip.frame_count).c_str(),
              console::with_thousands(clip.header_frame_count).c_str());
  std::printf("frame time:  %.7f s (%.2f fps), duration %.2f s\n", clip.frame_time,
              clip.frames_per_second(), clip.frame_count * clip.frame_time);
  std::vector<std::string> warnings = clip.warnings;
  if (!options.model.empty())
    std::printf("retargeted:  %s\n", retargeting(io::load_bvh(file), options, target_model(options),
                                                 target_name_map(options), warnings)
                                         .c_str());
  print_warnings(warnings);
  std::printf("joint tree:\n");
  auto children_of = [&](int j) {
    std::vector<int> children;
    for (int c = 0; c < static_cast<int>(clip.joints.size()); ++c)
      if (clip.joints[c].parent == j) children.push_back(c);
    return children;
  };
  auto label = [&](int j) {
    std::string text = clip.joints[j].name + " [";
    for (std::size_t k = 0; k < clip.joints[j].channels.size(); ++k)
      text += (k ? " " : "") + std::string(motion::channel_name(clip.joints[j].channels[k]));
    return text + "]";
  };
  for (int j = 0; j < static_cast<int>(clip.joints.size()); ++j)
    if (clip.joints[j].parent < 0) print_tree(children_of, label, j, 0);
  return 0;
}

}  // namespace

Command add_inspect_command(CLI::App& sweepctl) {
  CLI::App* command = sweepctl.add_subcommand(
      "inspect", "counts, joint tree, UVs, bounds and weights of a .glb/.gltf/.fbx/.dae/.bvh file");
  command->footer(
      "Prints counts, the joint tree, UV presence, bounding box and height, skin weight\n"
      "statistics, the detected rig map (each part's joints, found by name or by shape) and\n"
      "what is swept versus skinned (models), or channels, frames and frame rate (clips), and\n"
      "warnings. With --model MODEL a .bvh clip (or each animation of a model file) is also\n"
      "retargeted onto MODEL as `pose --bvh` (`--clip-from`) does: how its joints matched, and\n"
      "warnings naming the clip joints that drive nothing and the model joints left without\n"
      "motion. A .sweepbind prints its sweeps, what each was bound with (keys per link,\n"
      "orientation curve, the bind options' or the self-check's choice) and the binding's\n"
      "self-check run again: a warning per body region where the sweep is worse than the\n"
      "better of LBS and DQS on the range of motion's peaks (edge stretch as l / l_rest).");
  auto options = std::make_shared<InspectCommandOptions>();
  const CLI::Validator known_type(
      [](std::string& name) -> std::string {
        const std::string type = file_type(name);
        for (const char* known : {".bvh", ".glb", ".gltf", ".fbx", ".dae", ".sweepbind"})
          if (type == known) return "";
        return name + ": unknown file type '" + type +
               "' (expected .glb, .gltf, .fbx, .dae, .bvh or .sweepbind)";
      },
      "");
  command
      ->add_option("FILE", options->file,
                   "a .glb/.gltf/.fbx/.dae model, a .bvh motion clip or a .sweepbind binding")
      ->type_name("")
      ->required()
      ->check(known_type);
  CLI::Option* model =
      command
          ->add_option("--model", options->model,
                       "a .glb/.gltf/.fbx/.dae/.sweepbind model to retarget FILE's clip (a .bvh, "
                       "or each animation of a model file) onto, naming what is left unmapped")
          ->type_name("MODEL")
          ->check(CLI::ExistingFile);
  command
      ->add_option("--bvh-map", options->bvh_map,
                   "with --model: a JSON joint name map {\"clip joint\": \"model joint\"}")
      ->type_name("MAP")
      ->check(CLI::ExistingFile)
      ->needs(model);
  return {command, [options] {
            const std::string type = file_type(options->file);
            if (type == ".bvh") return inspect_motion(*options);
            return type == ".sweepbind" ? inspect_binding(*options) : inspect_model(*options);
          }};
}

}  // namespace sweepd::cli
