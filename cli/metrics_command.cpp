// sweepctl metrics: how well each deformation method keeps the body's shape — per body part
// volume change (closed mesh region and sweep integral), smallest limb section ratio,
// crossing triangle pairs, whole-body contact pairs (skin through skin, less the rest pose's own:
// deform/features/skin_contact.h), the longest and shortest edge as length ratios l / l_rest,
// per body part the crease (largest dihedral
// change from rest, anywhere and at the sweep's keys; the posed sweep's kink at its keys for sweep
// methods; metrics/crease_metrics.h) and the rest-pose error — for one pose or over a clip
// (worst, mean and the frame of the worst) — and the candy wrapper (smallest limb section ratio
// with both forearms twisted 90° and 180°), as a table, JSON or CSV.
// With --server the daemon deforms and the metrics are measured here on its vertices; the
// part regions and section planes come from binding the served mesh here; the sweep integral
// (the deformation's own sweep state) is not available remotely.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <thread>

#include "cli/commands.h"
#include "cli/posed_model.h"
#include "cli/remote_posed_model.h"
#include "console/command_line.h"
#include "console/progress_bar.h"
#include "deform/binding/bind.h"
#include "deform/features/collision_model.h"
#include "deform/features/whole_body_detector.h"
#include "deform/job/deform_job.h"
#include "deform/model/forward_kinematics.h"
#include "gpu/sheet/deform_with.h"
#include "io/bvh/bvh_load.h"
#include "io/json/rig_map_json.h"
#include "metrics/crease_metrics.h"
#include "metrics/quality_metrics.h"
#include "motion/retarget.h"

namespace sweepd::cli {

namespace {

const char* const kLocalMethods = "sweep,sweep+volume,lbs,dqs";
const char* const kServerMethods = "sweep,lbs,dqs";
const char* const kServerNote =
    "positions from the server; part regions and section planes from binding the served mesh "
    "here; sweep integral unavailable remotely";

using Method = deform::MethodChoice;

struct MetricsCommandOptions {
  PosingArguments posing;
  std::vector<Method> methods;  // --method, else kLocalMethods or kServerMethods
  int step = 1;
  bool json = false, csv = false;
  bool one_frame = false;  // --frame given (else a clip is measured whole or by --frames)
  bool per_frame = false;  // --per-frame: whole-body contact pairs of every frame, per method
};

// Whole-body contact pairs of posed positions: the skin's intersecting pairs (WholeBodyDetector,
// every hardware thread) less those the rest mesh has itself.
class ContactCounter {
 public:
  explicit ContactCounter(const deform::CollisionModel& model) : model_(model) {}
  int count(std::span<const glm::vec3> positions) {
    detector_.detect(positions, model_.regions.welded_indices, model_.contact.skin_triangles,
                     pairs_, static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
    deform::remove_rest_pairs(model_.contact.rest_pairs, pairs_);
    return static_cast<int>(pairs_.size());
  }

 private:
  const deform::CollisionModel& model_;
  deform::WholeBodyDetector detector_;
  std::vector<deform::TrianglePair> pairs_;
};

// One metric over the measured frames: the worst value (by `badness`), its frame, the mean.
struct Series {
  std::string name;
  double worst = 0.0, worst_badness = -1.0, sum = 0.0;
  int worst_frame = -1, count = 0;
  void add(double value, double badness, int frame) {
    sum += value;
    ++count;
    if (badness > worst_badness) worst = value, worst_badness = badness, worst_frame = frame;
  }
  double mean() const { return count ? sum / count : 0.0; }
};

struct MethodReport {
  std::string method;
  double rest_error_m = 0.0;
  std::vector<Series> series;
  std::vector<int> contact_pairs;  // per measured frame
};

// Deforms a pose with one method into positions; returns a SweepPoser posed to that pose (its
// section planes; its sweep integral when the poser holds the deformation's own sweep state).
using PoseDeformer =
    std::function<const deform::SweepPoser&(deform::Pose, std::vector<glm::vec3>&)>;

// The method deformed in this process (the context's poser holds the sweep state); folding's
// pairs from `collision` (null: the CPU reference).
PoseDeformer local_deformer(const Method& m, const deform::ModelRuntime& runtime,
                            deform::DeformContext& context, LocalCollision* collision) {
  return [&runtime, &context, m, collision](
             deform::Pose pose, std::vector<glm::vec3>& positions) -> const deform::SweepPoser& {
    return sheet::deform_with(m, runtime, context, collision, std::move(pose), positions);
  };
}

PoseDeformer server_deformer(const Method& m, RemotePosedModel& remote, deform::SweepPoser& poser) {
  return [&remote, &poser, m](deform::Pose pose,
                              std::vector<glm::vec3>& positions) -> const deform::SweepPoser& {
    std::vector<glm::vec3> normals;
    remote.deform_pose(pose, m.method,
                       m.preserve_volume ? protocol::Features::Volume
                       : m.contact ? protocol::Features::Folding | protocol::Features::Protrusion |
                                         protocol::Features::Contact
                       : m.collision ? protocol::Features::Folding | protocol::Features::Protrusion
                                     : protocol::Features::NONE,
                       positions, normals);
    const deform::Skeleton& skeleton = remote.model().skeleton;
    if (const std::string problem = deform::normalize_and_validate(pose, skeleton);
        !problem.empty())
      throw std::invalid_argument(problem);
    std::vector<glm::mat4> world(skeleton.joints.size());
    deform::forward_kinematics(skeleton, pose, world);
    poser.set_pose(world);
    return poser;
  };
}

// `sweep_state`: whether `deform`'s poser holds the deformation's own sweep (then the sweep
// integral is reported).
MethodReport measure_method(const Method& m, const deform::BoundModel& bound,
                            const PoseDeformer& deform, bool sweep_state,
                            const std::function<deform::Pose(int)>& pose_of,
                            const metrics::QualityMeter& meter,
                            const metrics::CreaseMeter& crease_meter, ContactCounter& contact,
                            const std::vector<int>& frames, console::ProgressBar* bar, int done,
                            int total) {
  MethodReport report;
  report.method = m.name;
  std::vector<glm::vec3> positions(bound.model.vertex_count());
  deform(deform::rest_pose(bound.model.skeleton), positions);
  report.rest_error_m = metrics::largest_distance(positions, bound.model.positions);

  const bool sweep = sweep_state && m.method == deform::DeformMethod::kSweep;
  for (const deform::BoundSweep& s : bound.sweeps)
    report.series.push_back({std::string(deform::to_string(s.part)) + " mesh volume %"});
  if (sweep)
    for (const deform::BoundSweep& s : bound.sweeps)
      report.series.push_back({std::string(deform::to_string(s.part)) + " sweep integral %"});
  for (const char* name :
       {"smallest section ratio", "crossing triangle pairs", "whole-body contact pairs",
        "longest edge l/l_rest", "shortest edge l/l_rest"})
    report.series.push_back({name});
  for (const deform::BoundSweep& s : bound.sweeps) {
    const std::string part = deform::to_string(s.part);
    report.series.push_back({part + " crease deg"});
    report.series.push_back({part + " crease at keys deg"});
    if (sweep) report.series.push_back({part + " kink deg"});
  }
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const deform::SweepPoser& poser = deform(pose_of(frames[i]), positions);
    const metrics::QualityMetrics q = meter.measure(positions, poser, sweep);
    const metrics::CreaseMetrics crease = crease_meter.measure(positions, sweep ? &poser : nullptr);
    std::size_t k = 0;
    for (const metrics::PartMetrics& part : q.parts) {
      const double percent = 100.0 * part.mesh_volume_change;
      report.series[k++].add(percent, std::abs(percent), frames[i]);
    }
    if (sweep)
      for (const metrics::PartMetrics& part : q.parts) {
        const double percent = 100.0 * part.sweep_volume_change;
        report.series[k++].add(percent, std::abs(percent), frames[i]);
      }
    report.series[k++].add(q.smallest_section_ratio, -q.smallest_section_ratio, frames[i]);
    report.series[k++].add(q.self_intersections, q.self_intersections, frames[i]);
    report.contact_pairs.push_back(contact.count(positions));
    report.series[k++].add(report.contact_pairs.back(), report.contact_pairs.back(), frames[i]);
    report.series[k++].add(q.longest_edge_ratio, q.longest_edge_ratio, frames[i]);
    report.series[k++].add(q.shortest_edge_ratio, -q.shortest_edge_ratio, frames[i]);
    for (const metrics::RegionCrease& region : crease.regions) {
      report.series[k++].add(region.dihedral_change, region.dihedral_change, frames[i]);
      report.series[k++].add(region.dihedral_change_at_keys, region.dihedral_change_at_keys,
                             frames[i]);
      if (sweep) report.series[k++].add(region.kink, region.kink, frames[i]);
    }
    if (bar) bar->update(static_cast<double>(done + i + 1) / total, "measuring " + m.name);
  }
  // The candy wrapper: both forearms twisted at the wrist, not a clip frame (-1).
  for (const float degrees : {90.0f, 180.0f}) {
    const deform::SweepPoser& poser =
        deform(metrics::forearm_twist_pose(bound, degrees), positions);
    const double ratio = meter.measure(positions, poser, sweep).smallest_section_ratio;
    Series twist{"candy wrapper " + std::to_string(static_cast<int>(degrees)) + " deg section"};
    twist.add(ratio, -ratio, -1);
    report.series.push_back(twist);
  }
  return report;
}

void print_table(const std::vector<MethodReport>& reports, std::size_t frames,
                 const std::string& source) {
  const bool clip = frames > 1;
  if (!source.empty()) std::printf("%s\n", source.c_str());
  for (const MethodReport& r : reports) {
    std::printf("\n%s (rest-pose error %.3g mm)\n", r.method.c_str(), 1e3 * r.rest_error_m);
    if (clip) std::printf("  %-34s %10s %10s %8s\n", "metric", "worst", "mean", "at frame");
    for (const Series& s : r.series) {
      if (clip)
        std::printf("  %-34s %10.3f %10.3f %8d\n", s.name.c_str(), s.worst, s.mean(),
                    s.worst_frame);
      else
        std::printf("  %-34s %10.3f\n", s.name.c_str(), s.worst);
    }
  }
}

// Whole-body contact pairs frame by frame, a column per method.
void print_contact_per_frame(const std::vector<MethodReport>& reports,
                             const std::vector<int>& frames) {
  std::printf("\nwhole-body contact pairs per frame\n  %8s", "frame");
  for (const MethodReport& r : reports) std::printf(" %14s", r.method.c_str());
  std::printf("\n");
  for (std::size_t i = 0; i < frames.size(); ++i) {
    std::printf("  %8d", frames[i]);
    for (const MethodReport& r : reports) std::printf(" %14d", r.contact_pairs[i]);
    std::printf("\n");
  }
}

// Sliding per contact over the whole clip, the same for every method: the feet's
// (motion::FootPlanting::contact_slides; the feet are skinned rigidly by all of them), for a
// retargeted clip whose feet are planted; then, per part, the other parts' that rest on the
// floor (motion::BodyContacts: knees, hips, hands, back, arms), where the clip rests one there.
void print_contact_slides(const PosedModel& posed) {
  const auto* retargeter = dynamic_cast<const motion::Retargeter*>(posed.clip());
  if (!retargeter || !retargeter->foot_planting()) return;
  const auto frame_pose = [&](int frame) { return retargeter->pose_at_frame(frame); };
  const std::vector<motion::FootPlanting::ContactSlide> slides =
      retargeter->foot_planting()->contact_slides(frame_pose);
  if (slides.empty()) {
    std::printf("\nfoot slide: no contacts (the clip never plants a foot)\n");
  } else {
    const motion::FootPlanting::ContactSlide* worst = &slides.front();
    double total = 0.0;
    for (const auto& contact : slides) {
      total += contact.slide;
      if (contact.slide > worst->slide) worst = &contact;
    }
    std::printf(
        "\nfoot slide per contact (whole clip, every method): worst %.2f cm (%s foot, "
        "frames %d-%d), mean %.2f cm over %zu contacts\n",
        100.0 * worst->slide, worst->side == 0 ? "left" : "right", worst->first, worst->last,
        100.0 * total / static_cast<double>(slides.size()), slides.size());
  }
  const motion::BodyContacts* contacts = retargeter->body_contacts();
  if (!contacts) return;
  const std::vector<motion::BodyContacts::ContactSlide> parts =
      contacts->contact_slides(frame_pose);
  if (parts.empty()) return;
  std::printf("slide per contact of the other parts resting on the floor:\n");
  for (int part = 0; part < motion::BodyContacts::kPartCount; ++part) {
    const motion::BodyContacts::ContactSlide* worst = nullptr;
    double total = 0.0;
    int count = 0;
    for (const auto& contact : parts) {
      if (contact.part != part) continue;
      total += contact.slide;
      ++count;
      if (!worst || contact.slide > worst->slide) worst = &contact;
    }
    if (count > 0)
      std::printf("  %-10s worst %.2f cm (frames %d-%d), mean %.2f cm over %d contacts\n",
                  motion::BodyContacts::name(part), 100.0 * worst->slide, worst->first, worst->last,
                  100.0 * total / count, count);
  }
}

// Whether the frames measured are the clip's frame numbers: not one pose of a --time sample, a
// --pose file or the rest pose, whose worst has no frame (-1 in CSV, null in JSON).
bool measures_clip_frames(const PosingArguments& posing) {
  return posing.has_clip() && !posing.time;
}

void print_json(const std::vector<MethodReport>& reports, const PosingArguments& posing,
                std::size_t frames, const std::string& source) {
  nlohmann::json out;
  out["model"] = posing.model.string();
  if (!source.empty()) out["source"] = source;
  if (posing.has_clip()) out["clip"] = posing.clip_file().string();
  if (posing.time) out["time_seconds"] = *posing.time;
  if (!posing.pose_file.empty()) out["pose"] = posing.pose_file.string();
  out["frames"] = frames;
  const bool clip_frames = measures_clip_frames(posing);
  for (const MethodReport& r : reports) {
    nlohmann::json method;
    method["method"] = r.method;
    method["rest_error_m"] = r.rest_error_m;
    for (const Series& s : r.series)
      method["metrics"].push_back(
          {{"name", s.name},
           {"worst", s.worst},
           {"mean", s.mean()},
           {"worst_frame",
            clip_frames && s.worst_frame >= 0 ? nlohmann::json(s.worst_frame) : nlohmann::json()}});
    method["contact_pairs_per_frame"] = r.contact_pairs;
    out["methods"].push_back(method);
  }
  std::printf("%s\n", out.dump(2).c_str());
}

void print_csv(const std::vector<MethodReport>& reports, const PosingArguments& posing) {
  const bool clip_frames = measures_clip_frames(posing);
  std::printf("method,metric,worst,mean,worst_frame\n");
  for (const MethodReport& r : reports) {
    std::printf("%s,rest-pose error m,%.9g,%.9g,-1\n", r.method.c_str(), r.rest_error_m,
                r.rest_error_m);
    for (const Series& s : r.series)
      std::printf("%s,%s,%.9g,%.9g,%d\n", r.method.c_str(), s.name.c_str(), s.worst, s.mean(),
                  clip_frames ? s.worst_frame : -1);
  }
}

int metrics(const MetricsCommandOptions& options, const ServerAddress* server) {
  const PosingArguments& posing = options.posing;
  const std::vector<Method>& methods = options.methods;
  const std::string format = options.json ? "json" : options.csv ? "csv" : "";
  // Locally: the model bound here and deformed here. Remotely: deformed by the server, and
  // the served mesh bound here for the part regions and section planes.
  std::unique_ptr<PosedModel> local;
  std::unique_ptr<RemotePosedModel> remote;
  std::unique_ptr<deform::BoundModel> served_binding;
  std::unique_ptr<deform::SweepPoser> served_poser;
  std::function<deform::Pose(int)> pose_of;
  if (server) {
    remote = std::make_unique<RemotePosedModel>(posing, *server, ClipPosing::kHere);
    std::fprintf(stderr, "%s\n", remote->served_as().c_str());  // the name the server holds
    const deform::Model& model = remote->model();
    served_binding = std::make_unique<deform::BoundModel>(deform::bind(
        model, posing.rig.empty() ? deform::detect_rig_map(model.skeleton)
                                  : io::load_rig_map_json(posing.rig, model.skeleton)));
    served_poser = std::make_unique<deform::SweepPoser>(*served_binding);
    pose_of = [&remote](int frame) { return remote->pose(frame); };
  } else {
    local = std::make_unique<PosedModel>(posing);
    pose_of = [&local](int frame) { return local->pose(frame); };
  }
  const deform::BoundModel& bound = server ? *served_binding : local->bound();
  std::vector<int> frames;
  if (!posing.has_clip() || posing.time) {
    frames.push_back(0);
  } else {
    const bool whole_clip = !posing.frame_range && !options.one_frame;
    const int count = local ? local->frame_count() : io::load_bvh(posing.bvh).frame_count;
    const int last = whole_clip ? count - 1 : posing.frames.last;
    for (int f = posing.frames.first; f <= last; f += options.step) frames.push_back(f);
  }
  const metrics::QualityMeter meter(bound);
  const metrics::CreaseMeter crease_meter(bound);
  // Whole-body contact: the local runtime's contact model, else one of the served binding.
  std::unique_ptr<deform::CollisionModel> served_collision;
  if (server)
    served_collision =
        std::make_unique<deform::CollisionModel>(deform::make_collision_model(bound));
  ContactCounter contact(server ? *served_collision : local->runtime().collision());
  // sweep+features here: folding's pairs from the --collision backend.
  std::optional<LocalCollision> collision;
  if (!server && sheet::uses_collision(methods)) collision.emplace(posing.collision);
  std::vector<MethodReport> reports;
  {
    std::unique_ptr<console::ProgressBar> bar;
    if (frames.size() > 1) bar = std::make_unique<console::ProgressBar>("metrics");
    const int total = static_cast<int>(frames.size() * methods.size());
    std::unique_ptr<deform::ModelRuntime> runtime;
    if (!server) runtime = std::make_unique<deform::ModelRuntime>(bound);
    for (std::size_t m = 0; m < methods.size(); ++m) {
      deform::DeformContext context;
      const PoseDeformer deform =
          server ? server_deformer(methods[m], *remote, *served_poser)
                 : local_deformer(methods[m], *runtime, context, collision ? &*collision : nullptr);
      reports.push_back(measure_method(methods[m], bound, deform, !server, pose_of, meter,
                                       crease_meter, contact, frames, bar.get(),
                                       static_cast<int>(m * frames.size()), total));
    }
  }
  const std::string source = server ? "sweepd at " + server->address + ": " + kServerNote : "";
  if (format == "json") {
    print_json(reports, posing, frames.size(), source);
  } else if (format == "csv") {
    if (!source.empty()) std::fprintf(stderr, "%s\n", source.c_str());
    print_csv(reports, posing);
  } else {
    print_table(reports, frames.size(), source);
    if (local) print_contact_slides(*local);
    if (options.per_frame) print_contact_per_frame(reports, frames);
    if (collision) std::printf("%s\n", collision->summary().c_str());
  }
  return 0;
}

}  // namespace

Command add_metrics_command(CLI::App& sweepctl, const ServerAddress& server) {
  CLI::App* command = sweepctl.add_subcommand(
      "metrics", "volume, section, crossing and stretch metrics per method");
  command->footer(
      "Per body part the volume change (closed mesh region and sweep integral), the smallest\n"
      "limb section ratio, crossing triangle pairs, whole-body contact pairs (skin through\n"
      "skin anywhere, less the rest mesh's own; --per-frame lists them frame by frame), the\n"
      "longest and the shortest edge as length ratios l / l_rest, per body part the\n"
      "crease (largest change of dihedral angle from rest, anywhere and at the sweep's keys, and\n"
      "for sweep methods the posed sweep's kink at its keys, in degrees) and the rest-pose\n"
      "error, for one pose or over a clip (worst, mean and the frame of the worst; without\n"
      "--frame or --frames the whole clip); then the candy wrapper: the smallest limb section\n"
      "ratio with both forearms twisted 90 and 180 degrees at the wrists (frame -1).\n"
      "With --server the daemon deforms and the metrics are measured here on its vertices:\n"
      "default methods sweep,lbs,dqs; no sweep integral (it needs the server's sweep state).");
  auto options = std::make_shared<MetricsCommandOptions>();
  add_posing_flags(*command, options->posing, ClipFrames::kOneOrRange);
  add_collision_flag(*command, options->posing);
  add_method_list_flag(
      *command, "--method", [options](const Method& method) { options->methods.push_back(method); },
      "comma-separated methods (default: sweep,sweep+volume,lbs,dqs); sweep+volume is the "
      "sweep method with volume preservation (arms, legs, torso), sweep+features with folding "
      "and protrusion, sweep+contact with those and whole-body contact (pairs from "
      "--collision's backend)")
      ->type_name("LIST");
  command->add_option("--step", options->step, "with a clip: every Nth frame")
      ->type_name("N")
      ->check(console::whole_number(1, 1 << 20))
      ->capture_default_str();
  command->add_flag("--per-frame", options->per_frame,
                    "after the table, the whole-body contact pairs of every measured frame per "
                    "method (JSON always has them: contact_pairs_per_frame)");
  command->add_flag("--json", options->json, "machine-readable JSON instead of the table");
  command->add_flag("--csv", options->csv, "machine-readable CSV instead of the table");
  command->callback([options, command, &server] {
    if (options->json && options->csv) throw CLI::ValidationError("give --json or --csv, not both");
    check_method_flags(options->posing, !server.address.empty());
    options->one_frame = command->count("--frame") > 0;
    if (options->methods.empty())
      for (const std::string& name :
           console::split_list(server.address.empty() ? kLocalMethods : kServerMethods))
        options->methods.push_back(deform::methods_by_name().at(name));
  });
  return {
      command,
      [options, &server] { return metrics(*options, server.address.empty() ? nullptr : &server); },
      true};
}

}  // namespace sweepd::cli
