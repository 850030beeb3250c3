#include "cli/posing_arguments.h"

#include <map>
#include <string>
#include <vector>

#include "console/command_line.h"

namespace sweepd::cli {

CLI::Option* add_model_and_clip_flags(CLI::App& command, PosingArguments& out) {
  command
      .add_option("MODEL", out.model,
                  "a rigged .glb/.gltf/.fbx/.dae (bound on the spot as bind binds it: adapted) or a "
                  ".sweepbind file")
      ->type_name("")
      ->required();
  command.add_option("--rig", out.rig, "rig map override when binding a model file")
      ->type_name("RIG.json");
  add_orientation_flag(command, out.orientation);
  CLI::Option* bvh = command
                         .add_option("--bvh", out.bvh,
                                     "a BVH clip, retargeted onto the model by joint names "
                                     "and roles")
                         ->type_name("CLIP");
  command
      .add_option("--bvh-map", out.bvh_map,
                  "BVH joint name -> model joint name, for rigs the names do not match")
      ->type_name("MAP.json");
  command
      .add_option("--bvh-up",
                  "the clip's up axis (default: detected from its skeleton, feet to head); a "
                  "Z-up clip is turned Y-up")
      ->type_name("y|z")
      ->check(CLI::IsMember({"y", "z"}))
      ->each([&out](const std::string& name) { out.bvh_up = motion::up_axis_from_name(name); })
      ->needs(bvh);
  command
      .add_option("--feet",
                  "a retargeted clip's feet: planted (default: put on the floor by leg IK where "
                  "the clip sets them down) or free (where the retargeted rotations put them)")
      ->type_name("planted|free")
      ->check(CLI::IsMember({"planted", "free"}))
      ->each([&out](const std::string& feet) {
        out.feet = feet == "free" ? motion::Feet::kFree : motion::Feet::kPlanted;
        out.feet_given = true;
      });
  return bvh;
}

void add_posing_flags(CLI::App& command, PosingArguments& out, ClipFrames frames) {
  CLI::Option* bvh = add_model_and_clip_flags(command, out);
  CLI::Option* clip =
      command
          .add_option("--clip", out.clip,
                      "an animation (name, or index from 0) of MODEL's glTF, FBX or COLLADA file, "
                      "played on its own joints; with --clip-from, of that file (default 0)")
          ->type_name("NAME|INDEX")
          ->excludes(bvh);
  command
      .add_option("--clip-from", out.clip_from,
                  "a glTF, FBX or COLLADA file whose animation (--clip) is retargeted onto the "
                  "model by joint names and roles, like a BVH")
      ->type_name("FILE")
      ->excludes(bvh);
  CLI::Option* frame = command.add_option("--frame", "the clip frame (default 0)")
                           ->type_name("N")
                           ->check(console::whole_number(0, 1 << 30))
                           ->each([&out](const std::string& n) {
                             out.frames.first = out.frames.last = std::stoi(n);
                             out.frame_given = true;
                           });
  CLI::Option* time =
      command.add_option("--time", out.time, "seconds into the clip (from frame 0)")
          ->type_name("T")
          ->check(CLI::NonNegativeNumber)
          ->excludes(frame);
  command
      .add_option("--fps", out.fps,
                  "the frame rate --frame and --frames count at (the clip resampled; default: "
                  "the clip's own)")
      ->type_name("F")
      ->check(CLI::PositiveNumber);
  if (frames == ClipFrames::kOneOrRange) {
    const CLI::Validator range(
        [](std::string& text) -> std::string {
          if (console::parse_frame_range(text)) return "";
          const std::size_t dash = text.find('-');
          if (dash != std::string::npos) {
            const std::optional<int> a = console::parse_frame_number(text.substr(0, dash));
            const std::optional<int> b = console::parse_frame_number(text.substr(dash + 1));
            if (a && b && *a > *b)
              return "'" + text + "' is an empty range: its first frame comes after its last";
          }
          return "expected A-B with 0 <= A <= B, got '" + text + "'";
        },
        "");
    command.add_option("--frames", "clip frames A to B, inclusive, 0-based (over --frame)")
        ->type_name("A-B")
        ->check(range)
        ->each([&out](const std::string& text) {
          out.frames = *console::parse_frame_range(text);
          out.frame_range = true;
          out.frame_given = true;
        })
        ->excludes(time);
  }
  command
      .add_option("--pose", out.pose_file,
                  "a hand-written pose (format in io/json/pose_json.h) instead of a clip")
      ->type_name("POSE.json")
      ->excludes(bvh)
      ->excludes(clip)
      ->excludes("--clip-from");
}

void add_orientation_flag(CLI::App& command, deform::OrientationCurveKind& out) {
  console::add_choice(command, "--orientation", out,
                      std::map<std::string, deform::OrientationCurveKind>{
                          {"linear", deform::OrientationCurveKind::kLinear},
                          {"smooth", deform::OrientationCurveKind::kSmooth}},
                      "the sweeps' orientation curve when binding a glTF: linear (the paper's "
                      "piecewise-linear quaternions, default) or smooth (C2 cumulative "
                      "B-spline: no crease at the keys)")
      ->type_name("CURVE");
}

namespace {

// "" when every method of the comma-separated list is known, else the parser's message
// (an empty list names the empty method).
std::string method_list_problem(const std::string& list) {
  std::vector<std::string> given = console::split_list(list);
  if (given.empty()) given.push_back("");
  for (const std::string& name : given)
    if (std::string problem = deform::method_name_problem(name); !problem.empty()) return problem;
  return "";
}

}  // namespace

CLI::Option* add_method_list_flag(CLI::App& command, const std::string& flag,
                                  const std::function<void(const deform::MethodChoice&)>& take,
                                  const std::string& help) {
  return command
      .add_option_function<std::string>(
          flag,
          [take](const std::string& list) {
            for (const std::string& name : console::split_list(list))
              take(deform::parse_method_choice(name));
          },
          help)
      ->check(CLI::Validator(method_list_problem, ""));
}

void add_method_flags(CLI::App& command, PosingArguments& out) {
  command.add_option("--method", "sweep (default), lbs or dqs")
      ->type_name("M")
      ->check(CLI::Validator(
          [](std::string& name) {
            return deform::method_name_problem(name, deform::MethodNames::kPlainMethods);
          },
          ""))
      ->each([&out](const std::string& name) {
        out.method = deform::parse_method_choice(name, deform::MethodNames::kPlainMethods).method;
      });
  using Feature = bool deform::AnatomicalFeatures::*;
  console::add_choice_list(
      command, "--features",
      std::map<std::string, Feature>{{"folding", &deform::AnatomicalFeatures::folding},
                                     {"protrusion", &deform::AnatomicalFeatures::protrusion},
                                     {"volume", &deform::AnatomicalFeatures::volume},
                                     {"bulge", &deform::AnatomicalFeatures::bulge},
                                     {"contact", &deform::AnatomicalFeatures::contact}},
      [&out](const Feature& feature) { out.features.*feature = true; },
      "with sweep: any of folding,protrusion (collision, paper 4.3), volume (preservation, "
      "4.4), bulge (biceps, 4.3), contact (whole-body skin through skin, beyond the paper)")
      ->type_name("LIST");
  add_collision_flag(command, out);
}

void add_collision_flag(CLI::App& command, PosingArguments& out) {
  command
      .add_option(
          "--collision",
          "where folding and contact find intersecting triangles: gpu (EGL compute; llvmpipe "
          "allowed), cpu (the reference), auto (default: gpu on a hardware GPU, else cpu)")
      ->type_name("auto|gpu|cpu")
      ->check(CLI::IsMember({"auto", "gpu", "cpu"}))
      ->each([&out](const std::string& name) {
        out.collision = *gpu::parse_collision_choice(name);
        out.collision_given = true;
      });
}

void check_method_flags(const PosingArguments& arguments, bool on_server) {
  if (arguments.features.any() && arguments.method != deform::DeformMethod::kSweep)
    throw CLI::ValidationError("--features apply to --method sweep, not " +
                               std::string(deform::to_string(arguments.method)));
  if (arguments.collision_given && on_server)
    throw CLI::ValidationError(
        "--collision applies where sweepctl deforms; with --server the daemon's own "
        "--collision decides (its Stats say which)");
  if (!arguments.has_clip() && (arguments.frame_given || arguments.time || arguments.fps > 0.0f))
    throw CLI::ValidationError(
        "--frame, --frames, --time and --fps choose frames of a clip: give --bvh, --clip or "
        "--clip-from");
  if (arguments.feet_given && arguments.bvh.empty() && arguments.clip_from.empty())
    throw CLI::ValidationError(
        "--feet applies to a retargeted clip (--bvh or --clip-from); --clip plays the model's "
        "own animation as it is");
  if (arguments.feet == motion::Feet::kFree && on_server)
    throw CLI::ValidationError(
        "--feet free applies where sweepctl retargets the clip; with --server the daemon plants "
        "the feet");
  if (arguments.bvh_up && on_server)
    throw CLI::ValidationError(
        "--bvh-up applies where sweepctl reads the clip; with --server the daemon detects the "
        "clip's up axis from its skeleton");
}

}  // namespace sweepd::cli
