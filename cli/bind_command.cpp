// sweepctl bind MODEL -o MODEL.sweepbind: binds a rigged model to its control sweeps (paper §3)
// and prints what a person needs to judge the binding.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cli/commands.h"
#include "cli/model_loading.h"
#include "cli/posing_arguments.h"
#include "cli/segment_colours.h"
#include "cli/self_check_report.h"
#include "console/text_format.h"
#include "console/command_line.h"
#include "console/progress_bar.h"
#include "deform/blending/rigid_islands.h"
#include "deform/blending/sweep_blending.h"
#include "deform/mesh/welded_mesh.h"
#include "io/gltf/gltf_save.h"
#include "io/sweepbind/sweepbind.h"
#include "selfcheck/binding_self_check.h"

namespace sweepd::cli {

namespace {

// "head 2,345, left hand 1,200, ...": the fully skinned vertices per body part, largest first.
// A bone that carries an end its sweep stops at (OpenPose's forearm, its neck) counts as that end.
std::string skinned_by_part(const deform::BoundModel& bound) {
  const deform::Model& model = bound.model;
  std::vector<deform::BodyPart> part_of = deform::label_joints(bound.rig, model.skeleton);
  for (const deform::BoundSweep& sweep : bound.sweeps)
    if (sweep.ends_on_carried_end()) part_of[sweep.chain.back()] = deform::end_part(sweep.part);
  std::map<std::string, std::size_t> count;
  for (std::size_t v = 0; v < model.vertex_count(); ++v) {
    if (bound.vertices[v].skin_weight < 1.0f) continue;
    const deform::BodyPart part = part_of[model.strongest_joint(v)];
    ++count[part == deform::BodyPart::kNone ? "joints above the pelvis" : deform::to_string(part)];
  }
  std::vector<std::pair<std::string, std::size_t>> parts(count.begin(), count.end());
  std::sort(parts.begin(), parts.end(),
            [](const auto& a, const auto& b) { return a.second > b.second; });
  std::string text;
  for (const auto& [part, n] : parts)
    text += (text.empty() ? "" : ", ") + part + " " + console::with_thousands(n);
  return text.empty() ? "none" : text;
}

void print_sweep(const deform::BoundModel& bound, int s) {
  const deform::BoundSweep& sweep = bound.sweeps[s];
  const deform::Skeleton& skeleton = bound.model.skeleton;
  std::size_t primary = 0, blended = 0;
  for (const deform::VertexBinding& b : bound.vertices) {
    primary += b.sweep[0] == s;
    blended += (b.sweep[0] == s && b.sweep[1] >= 0) || b.sweep[1] == s || b.sweep[2] == s;
  }
  std::printf(
      "\nsweep %-10s %zu keys, %s vertices (%s shared with another sweep), volume %.5f m3\n",
      deform::to_string(sweep.part), sweep.rest_keys.size(), console::with_thousands(primary).c_str(),
      console::with_thousands(blended).c_str(), sweep.rest_volume);
  std::printf("  %-26s %-26s %7s %7s %8s %6s\n", "key", "centre (m)", "a (m)", "b (m)", "fit err",
              "area");
  for (std::size_t k = 0; k < sweep.rest_keys.size(); ++k) {
    const deform::KeyAnchor& anchor = sweep.anchors[k];
    std::string where = skeleton.joints[anchor.joint].name;
    if (anchor.is_on_carried_end() && anchor.fraction == 1.0f) {
      where += " +1.00 (carried end)";  // the end its bone carries begins here
    } else if (!anchor.is_joint_key()) {
      char fraction[16];
      std::snprintf(fraction, sizeof fraction, " +%.2f", anchor.fraction);
      where += fraction;
    }
    const deform::KeyEllipse& key = sweep.rest_keys[k];
    char offset[64] = "";
    if (key.offset != glm::vec2(0.0f))
      std::snprintf(offset, sizeof offset, "  (ellipse off the centre by %.1f, %.1f cm)",
                    100 * key.offset.x, 100 * key.offset.y);
    std::printf("  %-26s (%7.3f,%7.3f,%7.3f)  %7.4f %7.4f %8.4f %6.3f%s%s\n", where.c_str(),
                key.centre.x, key.centre.y, key.centre.z, key.a, key.b, sweep.key_fit_errors[k],
                sweep.key_area_ratios[k], sweep.key_fallback[k] ? "  (copied: cut unusable)" : "",
                offset);
  }
}

// The bound mesh coloured by segment and blend share, with the key ellipses as line loops.
void write_debug_gltf(const deform::BoundModel& bound, const std::filesystem::path& file) {
  io::SaveOptions options;
  for (const glm::vec3& c : segment_colours(bound)) options.vertex_colors.emplace_back(c, 1.0f);
  constexpr int kLoopPoints = 48;
  for (const deform::BoundSweep& sweep : bound.sweeps)
    for (const deform::KeyEllipse& key : sweep.rest_keys) {
      const glm::mat3 r = glm::mat3_cast(key.orientation);
      const glm::vec3 ellipse_centre = key.centre + r * glm::vec3(key.offset, 0.0f);
      std::vector<glm::vec3> loop;
      for (int i = 0; i < kLoopPoints; ++i) {
        const float theta = 2.0f * static_cast<float>(M_PI) * i / kLoopPoints;
        loop.push_back(ellipse_centre + key.a * std::cos(theta) * r[0] +
                       key.b * std::sin(theta) * r[1]);
      }
      options.line_loops.push_back(std::move(loop));
    }
  io::save_gltf(bound.model, file, options);
}

// "rigid islands: 12 pieces, 3,400 vertices (left knee 1,200, ...)": the pieces skinning moves
// rigidly, which the binding leaves to it (deform/blending/rigid_islands.h), by their joint.
void print_rigid_islands(const deform::Model& model) {
  const std::vector<int> joint_of =
      deform::rigid_island_joints(model, deform::weld_mesh(model.positions, model.indices));
  std::map<std::string, std::size_t> count;
  for (const int joint : joint_of)
    if (joint >= 0) ++count[model.skeleton.joints[joint].name];
  if (count.empty()) return;
  std::size_t total = 0;
  std::string text;
  for (const auto& [joint, n] : count) {
    total += n;
    text += (text.empty() ? "" : ", ") + joint + " " + console::with_thousands(n);
  }
  std::printf("rigid islands (one joint each, skinned so they stay rigid): %s vertices (%s)\n",
              console::with_thousands(total).c_str(), text.c_str());
}

// The self-check's verdict: one line, then a warning per region where the sweep is still worse
// than skinning on the range of motion's peaks.
struct BindCommandOptions {
  std::filesystem::path model, out, rig, debug_gltf;
  deform::BindOptions bind;
  bool adapt = true;  // --no-adapt: keep bind's sweeps as fitted (selfcheck::adapt_binding)
  bool sweep_carried_ends = false;  // deform::bind's
};

int bind_model(const BindCommandOptions& options) {
  const LoadedModel loaded = load_model_and_rig(options.model, options.rig);
  selfcheck::CheckedBinding checked;
  {
    console::ProgressBar bar("binding " + options.model.filename().string());
    checked = selfcheck::bind_checked(
        loaded.model, loaded.rig, options.bind, options.adapt,
        [&](double f, std::string_view stage) { bar.update(f, stage); },
        options.sweep_carried_ends);
  }
  const deform::BoundModel& bound = checked.bound;
  const selfcheck::BindingVerdict& verdict = checked.verdict;
  const double seconds = checked.bind_seconds + checked.check_seconds;
  io::save_sweepbind(bound, options.out);

  const std::vector<glm::vec3> rebuilt = deform::rest_positions_from_binding(bound);
  float worst = 0.0f, lo = 1e30f, hi = -1e30f;
  std::size_t skinned = 0;
  for (std::size_t v = 0; v < rebuilt.size(); ++v) {
    worst = std::max(worst, glm::length(rebuilt[v] - loaded.model.positions[v]));
    lo = std::min(lo, loaded.model.positions[v].y);
    hi = std::max(hi, loaded.model.positions[v].y);
    skinned += bound.vertices[v].skin_weight >= 1.0f;
  }
  std::printf("bound %s: %s vertices, %zu sweeps, rig '%s' (%.2f s, of which the self-check%s "
              "%.2f s over %zu poses)\n",
              options.model.filename().string().c_str(),
              console::with_thousands(loaded.model.vertex_count()).c_str(), bound.sweeps.size(),
              bound.rig.convention.c_str(), seconds, options.adapt ? " and adaptation" : "",
              checked.check_seconds, verdict.pose_names.size());
  for (int s = 0; s < static_cast<int>(bound.sweeps.size()); ++s) print_sweep(bound, s);
  // Coverage said out loud: the vertices no sweep moves, by the body part of their strongest
  // joint (hands, feet and head always; a one-joint torso or neck, a forearm without a hand joint
  // (unless --sweep-carried-ends) or an absent limb where the rig's warnings say so).
  std::printf("\nskinned only: %s vertices (%s)\n", console::with_thousands(skinned).c_str(),
              skinned_by_part(bound).c_str());
  // --sweep-carried-ends: the rig's warnings (printed before binding) say these parts are
  // skinned; here they are not.
  for (const deform::BoundSweep& sweep : bound.sweeps)
    if (sweep.ends_on_carried_end())
      std::printf("carried end: the %s is swept past '%s' to the %s found on the mesh, %.1f cm "
                  "on; beyond it the %s is skinned, rigid with '%s'\n",
                  deform::to_string(sweep.part),
                  bound.model.skeleton.joints[sweep.chain.back()].name.c_str(),
                  sweep.part == deform::BodyPart::kNeck ? "neck's top" : "wrist",
                  100.0f * glm::distance(sweep.rest_keys.back().centre,
                                         glm::vec3(bound.model.skeleton.world_rest_matrices()
                                                       [sweep.chain.back()][3])),
                  deform::to_string(deform::end_part(sweep.part)),
                  bound.model.skeleton.joints[sweep.chain.back()].name.c_str());
  print_rigid_islands(bound.model);
  std::printf("rest-pose error: max %.3g m (%.3g x height)\n", worst, worst / (hi - lo));
  print_self_check(bound, verdict,
                   options.adapt ? std::optional<int>(checked.before.worse_pairs()) : std::nullopt);
  std::printf("wrote %s\n", options.out.string().c_str());
  if (!options.debug_gltf.empty()) {
    write_debug_gltf(bound, options.debug_gltf);
    std::printf("wrote %s (segments as vertex colours, key ellipses as line loops)\n",
                options.debug_gltf.string().c_str());
  }
  return 0;
}

}  // namespace

Command add_bind_command(CLI::App& sweepctl) {
  CLI::App* command = sweepctl.add_subcommand(
      "bind", "bind a rigged model to its control sweeps, write .sweepbind");
  command->footer(
      "Prints per sweep the key ellipses (centre, half-axes, fit error, area ratio, the\n"
      "ellipse's in-plane offset from the centre where it has one), the bound vertices, and the\n"
      "rest-pose reconstruction error. --orientation smooth stores the C2 orientation curve in\n"
      "the binding (the server and pose use it from there). Then the binding checks itself:\n"
      "the peaks of the body's range of motion (`sweepctl rom`) deformed with the sweep, LBS\n"
      "and DQS, and a warning for each body region where the sweep stretches an edge (length\n"
      "ratio l / l_rest) more than 1.02x the better of the two, or flips more triangles;\n"
      "`sweepctl check` measures the same on every 5th frame. A sweep that loses is fitted\n"
      "again where a refit wins without bringing any pose nearer to losing (--no-adapt: not).");
  auto options = std::make_shared<BindCommandOptions>();
  command->add_option("MODEL", options->model, "a rigged .glb/.gltf/.fbx/.dae model")
      ->type_name("")
      ->required();
  command
      ->add_option("-o", options->out,
                   "the binding file to write (read back by the server and by pose)")
      ->type_name("OUT.sweepbind")
      ->required();
  command
      ->add_option("--rig", options->rig,
                   "which joints form torso, neck, arms and legs (default: detected)")
      ->type_name("RIG.json");
  command
      ->add_option("--keys-per-link", options->bind.intermediate_keys_per_link,
                   "intermediate key ellipses per link")
      ->type_name("N")
      ->check(console::whole_number(0, 8))
      ->capture_default_str();
  add_orientation_flag(*command, options->bind.orientation_curve);
  command
      ->add_option("--debug-gltf", options->debug_gltf,
                   "the mesh coloured by sweep and blend share, with every key ellipse as a "
                   "line loop, for a glTF viewer")
      ->type_name("OUT.glb");
  command->add_flag(
      "--sweep-carried-ends", options->sweep_carried_ends,
      "where a forearm bone carries the hand or a one-joint neck the head (no hand or head joint: "
      "OpenPose), sweep the forearm from the elbow to the wrist and the neck to below the head, "
      "both found on the mesh (narrowest section), the hand and head skinned rigid with the bone; "
      "off by default: on the corpus's OpenPose body the sweep is then worse than skinning in more "
      "(frame, region) pairs (docs/carried_ends.md)");
  command->add_flag(
      "--adapt,!--no-adapt", options->adapt,
      "where the self-check finds a sweep worse than skinning, fit it again with fewer link "
      "keys and/or the other orientation curve and keep what leaves fewer (pose, region) pairs "
      "worse and no pair worse or nearer to losing (recorded per sweep in the binding; on by "
      "default; the self-check and adaptation cost about 2.3x bind's own CPU time; --no-adapt keeps "
      "the sweeps as fitted)");
  return {command, [options] { return bind_model(*options); }};
}

}  // namespace sweepd::cli
