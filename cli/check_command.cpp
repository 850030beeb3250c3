// sweepctl check MODEL: is the sweep ever worse than skinning on this body? (issue 47) Poses the
// model through its range of motion (motion/range_of_motion.h; or --bvh / --clip / --clip-from),
// deforms every measured frame with each method, and measures each body region
// (metrics/region_quality.h): the largest edge stretch and squash as length ratios l / l_rest,
// the largest crease, flipped triangles. A region where a sweep method stretches an edge more
// than kTolerance times the better of LBS and DQS in some frame, or flips more triangles than
// it, fails: the command then exits 1, so users can put it in their own CI. The verdict looks
// at the edges and triangles a sweep moves: the rest of a region (fingers, toes, the face) is
// the sweep method's skinned remainder, LBS itself, and LBS against DQS is not the sweep's
// doing.
#include <algorithm>
#include <cstdio>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "cli/local_sheet.h"
#include "cli/posed_model.h"
#include "console/command_line.h"
#include "console/progress_bar.h"
#include "gpu/sheet/deform_with.h"
#include "io/files/write_whole_file.h"
#include "metrics/region_quality.h"
#include "motion/own_skeleton_clip.h"
#include "motion/range_of_motion.h"

namespace sweepd::cli {

namespace {

using Method = deform::MethodChoice;
using deform::DeformMethod;

constexpr double kTolerance = metrics::kSkinningTolerance;
// The range of motion's moves peak at their 15th frame: every 5th frame holds every peak.
constexpr int kRomStep = motion::kRomFramesPerMove / 6;
static_assert(motion::kRomFramesPerMove / 2 % kRomStep == 0);

struct CheckCommandOptions {
  PosingArguments posing;
  std::vector<Method> methods;  // default sweep, lbs, dqs
  int step = 0;                 // 0: every 5th frame of the ROM (its peaks), every 10th of a clip
  bool json = false, markdown = false;
  bool sections = false;        // --sections: limb sections and crossing pairs too
  std::filesystem::path sheet;  // --sheet: the worst frames' contact sheet
  std::string focus;            // --focus: its close-ups' joint
  float azimuth = 0.0f;         // --azimuth: its view, degrees from the front towards the left
  std::vector<int> frames;      // --sheet-frames: its frames instead of the worst
};

// One method's worst figures in one region over the measured frames.
struct Worst {
  double stretch = 1.0, squash = 1.0, crease = 0.0;
  int flipped = 0;
  int stretch_frame = -1, squash_frame = -1, crease_frame = -1, flipped_frame = -1;
  void add(const metrics::RegionFigures& f, int frame) {
    if (f.stretch > stretch) stretch = f.stretch, stretch_frame = frame;
    if (f.squash < squash) squash = f.squash, squash_frame = frame;
    if (f.crease > crease) crease = f.crease, crease_frame = frame;
    if (f.flipped > flipped) flipped = f.flipped, flipped_frame = frame;
  }
};

// Where one sweep method is worse than the better baseline in one region.
struct Verdict {
  bool swept = false;         // whether the region has swept edges (else it is skinned only)
  int worse_frames = 0;       // frames whose stretch or flipped count is worse
  int worst_frame = -1;       // the frame with the largest stretch excess over the baseline
  double excess = 0.0;        // sweep ratio / (kTolerance x baseline ratio) there
  double sweep = 0.0, baseline = 0.0;  // the two ratios there
  struct Frame {
    int frame;
    double sweep, baseline;  // the swept edges' worst stretch and the better baseline's
  };
  std::vector<Frame> worse;  // each worse frame, for --json's "worse" list
};

struct Report {
  std::string clip;                    // what was played
  std::vector<int> frames;             // measured
  std::vector<deform::BodyPart> regions;
  std::vector<std::vector<Worst>> worst;      // [method][region]
  std::vector<std::vector<Verdict>> verdict;  // [method][region], sweep methods only
  std::function<std::string(int)> frame_label;
  // --sections: per method, over the frames measured for them, the smallest limb section ratio
  // and the most crossing triangle pairs (metrics::QualityMeter, whole body), with their frames.
  struct Whole {
    double section = 1.0;
    int crossing = 0, section_frame = -1, crossing_frame = -1;
  };
  std::vector<Whole> whole;
};

bool is_sweep(const Method& m) { return m.method == DeformMethod::kSweep; }

Report run_check(const CheckCommandOptions& options, const PosedModel& posed,
                 const motion::ClipPoses* clip, const motion::RangeOfMotion* rom) {
  const deform::BoundModel& bound = posed.bound();
  const std::vector<Method>& methods = options.methods;
  Report report;
  const int frame_count = clip ? clip->frame_count() : 1;
  const int step = options.step > 0 ? options.step : rom ? kRomStep : 10;
  for (int f = 0; f < frame_count; f += step) report.frames.push_back(f);
  const metrics::RegionMeter meter(bound);
  std::optional<metrics::QualityMeter> quality;
  if (options.sections) quality.emplace(bound);
  report.whole.assign(methods.size(), {});
  report.regions = meter.regions();
  const std::size_t regions = report.regions.size();
  report.worst.assign(methods.size(), std::vector<Worst>(regions));
  report.verdict.assign(methods.size(), std::vector<Verdict>(regions));
  int lbs = -1, dqs = -1;
  for (std::size_t m = 0; m < methods.size(); ++m) {
    if (methods[m].method == DeformMethod::kLbs) lbs = static_cast<int>(m);
    if (methods[m].method == DeformMethod::kDqs) dqs = static_cast<int>(m);
  }
  std::vector<std::vector<metrics::RegionFigures>> figures(methods.size());
  std::vector<glm::vec3> positions(bound.model.vertex_count());
  std::vector<deform::DeformContext> contexts(methods.size());
  // sweep+features and sweep+contact: folding's pairs from the --collision backend.
  std::optional<LocalCollision> collision;
  if (sheet::uses_collision(methods)) collision.emplace(options.posing.collision);
  console::ProgressBar bar("check");
  for (std::size_t i = 0; i < report.frames.size(); ++i) {
    const int frame = report.frames[i];
    const deform::Pose pose = clip ? clip->pose_at_frame(frame) : posed.pose(0);
    for (std::size_t m = 0; m < methods.size(); ++m) {
      const deform::SweepPoser& poser = sheet::deform_with(
          methods[m], posed.runtime(), contexts[m], collision ? &*collision : nullptr, pose,
          positions);
      figures[m] = meter.measure(positions, contexts[m].world_pose());
      // 30-45 ms a frame on the male: at every third measured frame (every move's peak and
      // rest on the range of motion).
      if (quality && i % 3 == 0) {
        const metrics::QualityMetrics q = quality->measure(positions, poser, false);
        Report::Whole& w = report.whole[m];
        if (q.smallest_section_ratio < w.section)
          w.section = q.smallest_section_ratio, w.section_frame = frame;
        if (q.self_intersections > w.crossing)
          w.crossing = q.self_intersections, w.crossing_frame = frame;
      }
      for (std::size_t r = 0; r < regions; ++r) report.worst[m][r].add(figures[m][r], frame);
    }
    // Each sweep method against the better baseline, frame by frame.
    for (std::size_t m = 0; m < methods.size() && lbs >= 0 && dqs >= 0; ++m) {
      if (!is_sweep(methods[m])) continue;
      for (std::size_t r = 0; r < regions; ++r) {
        const metrics::SkinningComparison c =
            metrics::compare_with_skinning(figures[m][r], figures[lbs][r], figures[dqs][r]);
        if (!c.swept) continue;
        Verdict& v = report.verdict[m][r];
        v.swept = true;
        v.worse_frames += c.worse;
        if (c.worse) v.worse.push_back({frame, c.sweep, c.baseline});
        if (c.excess > v.excess)
          v.excess = c.excess, v.worst_frame = frame, v.sweep = c.sweep, v.baseline = c.baseline;
      }
    }
    bar.update(static_cast<double>(i + 1) / report.frames.size(), "measuring",
               rom ? rom->move_at(frame) : "frame " + std::to_string(frame));
  }
  report.frame_label = [rom](int frame) {
    return rom ? std::to_string(frame) + " " + rom->move_at(frame) : std::to_string(frame);
  };
  return report;
}

int failing_regions(const Report& report, const std::vector<Method>& methods) {
  int failing = 0;
  for (std::size_t m = 0; m < methods.size(); ++m)
    for (const Verdict& v : report.verdict[m]) failing += v.worse_frames > 0;
  return failing;
}

// The last column: whether, how often and where a sweep method was worse than skinning.
std::string verdict_text(const Report& report, const std::vector<Method>& methods, std::size_t m,
                         std::size_t r) {
  if (!is_sweep(methods[m])) return "";
  const Verdict& v = report.verdict[m][r];
  if (!v.swept) return "skinned only (LBS)";
  if (v.worse_frames == 0) return "no";
  std::string text = std::to_string(v.worse_frames) + " frames";
  if (v.excess > 1.0) {
    char worst[160];
    std::snprintf(worst, sizeof worst, "; worst %s: %.2f against %.2f",
                  report.frame_label(v.worst_frame).c_str(), v.sweep, v.baseline);
    text += worst;
  }
  return text;
}

std::string summary(const Report& report, const std::vector<Method>& methods) {
  const int failing = failing_regions(report, methods);
  char text[200];
  if (failing == 0)
    std::snprintf(text, sizeof text,
                  "the sweep is nowhere worse than the better of LBS and DQS (tolerance %.2fx)",
                  kTolerance);
  else
    std::snprintf(text, sizeof text,
                  "the sweep is worse than the better of LBS and DQS in %d region%s (tolerance "
                  "%.2fx)",
                  failing, failing == 1 ? "" : "s", kTolerance);
  return text;
}

// --sections' figures, a line per method.
void print_whole(const Report& report, const std::vector<Method>& methods) {
  for (std::size_t m = 0; m < methods.size(); ++m) {
    const Report::Whole& w = report.whole[m];
    if (w.section_frame < 0) continue;
    std::printf("%-14s smallest limb section %.2f of rest (frame %s); crossing triangle pairs "
                "%d (frame %s)\n",
                methods[m].name.c_str(), w.section, report.frame_label(w.section_frame).c_str(),
                w.crossing, w.crossing_frame >= 0 ? report.frame_label(w.crossing_frame).c_str() : "-");
  }
}

void print_table(const Report& report, const std::vector<Method>& methods,
                 const std::string& model) {
  std::printf("%s on %s: %zu frames measured; length ratios l / l_rest; crease in degrees\n",
              model.c_str(), report.clip.c_str(), report.frames.size());
  std::printf("%-11s %-14s %8s  %-34s %7s %8s %8s  %s\n", "region", "method", "stretch",
              "at frame", "squash", "crease", "flipped", "worse than skinning");
  for (std::size_t r = 0; r < report.regions.size(); ++r)
    for (std::size_t m = 0; m < methods.size(); ++m) {
      const Worst& w = report.worst[m][r];
      std::printf("%-11s %-14s %8.2f  %-34.34s %7.2f %8.1f %8d  %s\n",
                  m == 0 ? deform::to_string(report.regions[r]) : "", methods[m].name.c_str(),
                  w.stretch, report.frame_label(w.stretch_frame).c_str(), w.squash, w.crease,
                  w.flipped, verdict_text(report, methods, m, r).c_str());
    }
  std::printf("%s: see the last column\n", summary(report, methods).c_str());
  print_whole(report, methods);
}

// One Markdown table, a row per region: each method's worst stretch and its frame, then each
// sweep method's verdict (docs/quality/, made by `make docs-quality`).
void print_markdown(const Report& report, const std::vector<Method>& methods) {
  std::printf("%zu frames; the largest edge length ratio l / l_rest of each region, at its frame\n\n",
              report.frames.size());
  std::printf("| region |");
  for (const Method& m : methods) std::printf(" %s |", m.name.c_str());
  for (const Method& m : methods)
    if (is_sweep(m)) std::printf(" %s worse than skinning |", m.name.c_str());
  std::printf("\n|---|");
  for (const Method& m : methods) std::printf(is_sweep(m) ? "---|---|" : "---|");
  std::printf("\n");
  for (std::size_t r = 0; r < report.regions.size(); ++r) {
    std::printf("| %s |", deform::to_string(report.regions[r]));
    for (std::size_t m = 0; m < methods.size(); ++m)
      std::printf(" %.2f (%s) |", report.worst[m][r].stretch,
                  report.frame_label(report.worst[m][r].stretch_frame).c_str());
    for (std::size_t m = 0; m < methods.size(); ++m)
      if (is_sweep(methods[m])) std::printf(" %s |", verdict_text(report, methods, m, r).c_str());
    std::printf("\n");
  }
  std::printf("\nworst over every region:");
  for (std::size_t m = 0; m < methods.size(); ++m) {
    double worst = 1.0;
    for (const Worst& w : report.worst[m]) worst = std::max(worst, w.stretch);
    std::printf("%s %s %.2f", m ? "," : "", methods[m].name.c_str(), worst);
  }
  std::printf("\n\n%s.\n", summary(report, methods).c_str());
}

void print_json(const Report& report, const std::vector<Method>& methods,
                const std::string& model) {
  nlohmann::json out;
  out["model"] = model;
  out["clip"] = report.clip;
  out["frames"] = report.frames.size();
  out["tolerance"] = kTolerance;
  for (std::size_t r = 0; r < report.regions.size(); ++r) {
    nlohmann::json region;
    region["region"] = deform::to_string(report.regions[r]);
    for (std::size_t m = 0; m < methods.size(); ++m) {
      const Worst& w = report.worst[m][r];
      nlohmann::json method = {{"method", methods[m].name},
                               {"stretch", w.stretch},
                               {"stretch_frame", w.stretch_frame},
                               {"squash", w.squash},
                               {"squash_frame", w.squash_frame},
                               {"crease_degrees", w.crease},
                               {"crease_frame", w.crease_frame},
                               {"flipped", w.flipped},
                               {"flipped_frame", w.flipped_frame}};
      if (report.whole[m].section_frame >= 0) {
        method["smallest_section"] = report.whole[m].section;
        method["crossing_pairs"] = report.whole[m].crossing;
      }
      if (is_sweep(methods[m])) {
        const Verdict& v = report.verdict[m][r];
        method["swept"] = v.swept;
        method["worse_frames"] = v.worse_frames;
        method["worst_excess_frame"] = v.worst_frame;
        method["worst_excess"] = v.excess;
        for (const Verdict::Frame& f : v.worse)
          method["worse"].push_back({{"frame", f.frame},
                                     {"at", report.frame_label(f.frame)},
                                     {"stretch", f.sweep},
                                     {"baseline_stretch", f.baseline}});
      }
      region["methods"].push_back(method);
    }
    out["regions"].push_back(region);
  }
  out["worse_than_skinning"] = failing_regions(report, methods) > 0;
  std::printf("%s\n", out.dump(2).c_str());
}

// The frames a person should look at: where each sweep method is furthest past the better
// baseline in a failing region, then where it stretches each region most; at most kSheetRows.
std::vector<int> worst_frames(const Report& report, const std::vector<Method>& methods) {
  constexpr std::size_t kSheetRows = 8;
  std::vector<std::pair<double, int>> ranked;  // (-priority, frame)
  for (std::size_t m = 0; m < methods.size(); ++m) {
    if (!is_sweep(methods[m])) continue;
    for (std::size_t r = 0; r < report.regions.size(); ++r) {
      const Verdict& v = report.verdict[m][r];
      if (v.worse_frames > 0 && v.worst_frame >= 0) ranked.push_back({-10.0 - v.excess, v.worst_frame});
      ranked.push_back({-report.worst[m][r].stretch, report.worst[m][r].stretch_frame});
    }
  }
  std::sort(ranked.begin(), ranked.end());
  std::vector<int> frames;
  for (const auto& [priority, frame] : ranked)
    if (frame >= 0 && frames.size() < kSheetRows &&
        std::find(frames.begin(), frames.end(), frame) == frames.end())
      frames.push_back(frame);
  std::sort(frames.begin(), frames.end());
  return frames;
}

void write_sheet(const CheckCommandOptions& options, const PosedModel& posed,
                 const motion::ClipPoses* clip, const Report& report) {
  sheet::SheetOptions grid;
  grid.methods = options.methods;
  grid.frames = options.frames.empty() ? worst_frames(report, options.methods) : options.frames;
  grid.focus = options.focus;
  grid.azimuth_degrees = options.azimuth;
  grid.cell_width = 200;
  grid.cell_height = 300;
  grid.heat = true;
  LocalSheet local(posed, grid, [clip, &posed](int frame) {
    return clip ? clip->pose_at_frame(frame) : posed.pose(0);
  });
  const sheet::SheetPicture picture = local.picture();
  io::write_whole_file(options.sheet, picture.png, "sweepctl check");
  std::string rows;
  for (int frame : grid.frames) rows += (rows.empty() ? "" : "; ") + report.frame_label(frame);
  std::fprintf(stderr, "wrote %s (%dx%d, stretch heat, frames %s)\n",
               options.sheet.string().c_str(), picture.width, picture.height, rows.c_str());
}

int check(const CheckCommandOptions& options) {
  const PosedModel posed(options.posing);
  std::unique_ptr<motion::RangeOfMotion> rom;
  std::unique_ptr<motion::OwnSkeletonClip> rom_player;
  const motion::ClipPoses* clip = posed.clip();
  std::string clip_name = options.posing.has_clip() ? options.posing.clip_file().string() : "";
  if (!options.posing.has_clip() && options.posing.pose_file.empty()) {
    rom = std::make_unique<motion::RangeOfMotion>(
        motion::range_of_motion(posed.model().skeleton, posed.bound().rig));
    rom_player = std::make_unique<motion::OwnSkeletonClip>(rom->clip, posed.model().skeleton);
    clip = rom_player.get();
    clip_name = "its range of motion (" + std::to_string(rom->moves.size()) + " moves)";
  } else if (!options.posing.pose_file.empty()) {
    clip_name = options.posing.pose_file.string();
  }
  Report report = run_check(options, posed, clip, rom.get());
  report.clip = clip_name;
  const std::string model = options.posing.model.string();
  if (!options.sheet.empty()) write_sheet(options, posed, clip, report);
  if (options.json)
    print_json(report, options.methods, model);
  else if (options.markdown)
    print_markdown(report, options.methods);
  else
    print_table(report, options.methods, model);
  return failing_regions(report, options.methods) > 0 ? 1 : 0;
}

}  // namespace

Command add_check_command(CLI::App& sweepctl) {
  CLI::App* command = sweepctl.add_subcommand(
      "check", "is the sweep worse than skinning anywhere on this body? (exit 1 if so)");
  command->footer(
      "Poses MODEL through its range of motion (every joint through its anatomical range,\n"
      "alone and combined: `sweepctl rom` writes it as a glTF animation), or --bvh, --clip,\n"
      "--clip-from's clip, deforms each measured frame with every method and measures each\n"
      "body region: the largest edge stretch and squash as length ratios l / l_rest, the\n"
      "largest crease (change of dihedral angle from rest), flipped triangles. A region where\n"
      "a sweep method stretches an edge more than 1.02x the better of LBS and DQS in some\n"
      "frame, or flips more triangles, is worse than skinning: the command exits 1. Judged\n"
      "on the edges a sweep moves; what no sweep moves (fingers, toes, the face) is skinned\n"
      "by LBS in every method and shown as \"skinned only (LBS)\".");
  auto options = std::make_shared<CheckCommandOptions>();
  add_posing_flags(*command, options->posing, ClipFrames::kOne);
  add_collision_flag(*command, options->posing);
  add_method_list_flag(
      *command, "--method", [options](const Method& method) { options->methods.push_back(method); },
      "comma-separated methods (default: sweep,lbs,dqs; lbs and dqs are always measured: the "
      "sweep methods are judged against them); sweep+features folds and protrudes with pairs "
      "from --collision's backend")
      ->type_name("LIST");
  command->add_option("--step", options->step,
                      "every Nth frame (default: 5 on the range of motion, where every move "
                      "peaks at a multiple of 5; 10 on a clip)")
      ->type_name("N")
      ->check(console::whole_number(1, 1 << 20));
  command->add_flag("--json", options->json, "machine-readable JSON instead of the table");
  command->add_flag("--markdown", options->markdown,
                    "a Markdown table (worst stretch per region and method, the verdict) instead")
      ->excludes("--json");
  command->add_flag("--sections", options->sections,
                    "also the smallest limb section ratio and the most crossing triangle pairs "
                    "per method (whole body, at every third measured frame; slower)");
  command
      ->add_option("--sheet", options->sheet,
                   "a contact sheet of the worst frames (where the sweep is furthest past "
                   "skinning, then where each region stretches most), methods side by side, "
                   "coloured by stretch")
      ->type_name("OUT.png");
  command->add_option("--focus", options->focus, "--sheet's close-ups: the camera frames this joint")
      ->type_name("JOINT")
      ->check(CLI::IsMember(sheet::focus_names()));
  command
      ->add_option("--azimuth", options->azimuth,
                   "--sheet's view: degrees from the body's front towards its left side")
      ->type_name("DEG")
      ->check(CLI::Range(-360.0f, 360.0f));
  command
      ->add_option("--sheet-frames", options->frames,
                   "--sheet's frames, comma-separated, instead of the worst")
      ->type_name("LIST")
      ->delimiter(',');
  command->callback([options] {
    check_method_flags(options->posing);
    if (options->methods.empty()) options->methods.push_back(deform::methods_by_name().at("sweep"));
    for (const char* baseline : {"lbs", "dqs"}) {
      const Method& m = deform::methods_by_name().at(baseline);
      if (std::none_of(options->methods.begin(), options->methods.end(),
                       [&](const Method& x) { return x.name == m.name; }))
        options->methods.push_back(m);
    }
  });
  return {command, [options] { return check(*options); }, false};
}

}  // namespace sweepd::cli
