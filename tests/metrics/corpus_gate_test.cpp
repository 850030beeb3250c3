// The corpus gate (issue 47 item 6), as far as it holds today. Every shared body — the shared
// male, the RiggedFigure, the four corpus bodies — and the mannequin at 6k, 20k and 72k
// vertices, each as is, mirrored and at 0.6x, bound as bind binds by default (adapted), on the
// peaks of its range of motion (motion/range_of_motion.h) and every 100th frame of both CMU
// clips: per frame and body region, is the sweep worse than the better of LBS and DQS
// (metrics::compare_with_skinning: its swept edges stretch more than 1.02x the better
// baseline's, as length ratios l / l_rest, or more of its swept triangles flip)?
//
// The target is never. Today it is not met (docs/quality/), so the count of worse
// (frame, region) pairs per body, over its three variants and three clips, is held to this
// stop's figure (kLedger): a change that makes the sweep worse than skinning somewhere new fails
// here; one that makes it better passes and should lower the ledger.
// Asserted as well, per variant and clip: the sweep's worst stretch over the torso, neck, arms
// and legs stays clearly below the better baseline's there (its advantage where it is better:
// the crotch and the armpit, where LBS and DQS reach 4-20x). Every edge of those regions
// counts, so handing the crotch or an armpit to skinning (which would clear the count above)
// fails here. The clip is not mirrored with the body: a mirrored body performs the mirror image
// of the motion, which is why its figures differ.
// And on both CMU clips, for the variants where it holds (kWithinTargetOnCmu), issue 47's target
// that no edge of those regions stretches past 3x its rest length.
// Printed per body besides: where its worse pairs are (WorseBreakdown), so that the largest
// class of them shows without a debugger.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "deform/binding/bind.h"
#include "io/bvh/bvh_load.h"
#include "io/gltf/gltf_load.h"
#include "mannequin/mannequin.h"
#include "metrics/region_quality.h"
#include "motion/own_skeleton_clip.h"
#include "motion/range_of_motion.h"
#include "motion/retarget.h"
#include "selfcheck/binding_self_check.h"
#include "tests/body_variants.h"
#include "tests/deform/shared_male.h"

namespace sweepd::metrics {
namespace {

namespace fs = std::filesystem;
using deform::DeformMethod;

constexpr int kClipStep = 100;

// Worse (frame, region) pairs per body, summed over as is, mirrored and 0.6x and over the range
// of motion's peaks and both clips, measured with the adapted binding (target: 0). Lowered when
// the skinned share's rise was limited along the surface (deform/blending/sweep_blending.h,
// kHandoverReach): from male 465, RiggedFigure 991, child 659, heavy female 474, OpenPose 486,
// heavy male 634, mannequins 263 / 391 / 408 (4771 in all) to male 399, child 516, heavy female
// 451, OpenPose 435, heavy male 531, mannequins 233 / 309 / 342; then when the share smoothing
// reached past where an arm meets another sweep (kArmShareSmoothingReach) and the OpenPose
// body's one-joint torso was swept up to its neck (RigMap::torso_sweep_chain), to the figures
// below (male 400 -> 381, child 519 -> 515, heavy female 449 -> 330, OpenPose 433 -> 96, heavy
// male 523 -> 523, 6k mannequin 234 -> 228, measured before and after on one machine). The
// 20k mannequin measured 311 -> 313 and the 72k 345 (not measured before): their entries stay,
// within the 2 % below; so does the RiggedFigure's 991 (993 before and after). Then the plane
// turn limit on the torso (deform/posing/plane_turn_limit.h), measured before and after on one
// machine: child 515 -> 495, heavy male 523 -> 473 (male 381, heavy female 330, OpenPose 96
// unchanged; the RiggedFigure and the mannequins 993 and 228 / 313 / 342-345, within the 2 %).
// Then two asymmetries of the measurement fixed, measured together on one machine: an edge
// between two regions counts in both (metrics::edge_regions; it counted in its first vertex's,
// which a mirrored copy's reversed winding changes) and the mirrored variants of the Mixamo and
// Unreal bodies have their sides' names swapped (tests/mirrored_model.h; they kept LeftArm on
// the right and were read as facing backwards): male 381 -> 378, RiggedFigure 993 -> 729, child
// 495 -> 354, heavy female 330 -> 148, OpenPose 96 -> 74, heavy male 473 -> 388, mannequins
// 228 -> 233, 313 -> 312, 345 -> 366 (their edges between two regions now count in both), 3,649
// -> 2,982 in all. Then one link key per link as bind's default (two before; the figures before
// are the ledger's, those after measured at stop 65 and the same as stop 64 measured): male
// 378 -> 332, RiggedFigure 729 -> 718, child 354 -> 309, heavy female 148 -> 120, OpenPose
// 74 -> 73, heavy male 388 -> 354, mannequins 233 -> 179, 312 -> 225, 366 -> 236; 2,982 ->
// 2,546 in all. Then a triangle counted in the region of each of its corners and flipped only
// against each corner's joint (metrics::triangle_regions, flipped_from_rest; it was its first
// corner's, which a re-export that rotates corners changes), measured before and after on one
// machine: male 332 -> 316, RiggedFigure 718 -> 727, child 309 -> 297, heavy female 120 -> 91,
// OpenPose 73 -> 44, heavy male 354 -> 360, mannequins 179 -> 164, 225 -> 217, 236 -> 236;
// 2,546 -> 2,452 in all. The pairs worse by flipped triangles alone went 521 -> 427, those worse
// by both flips and stretch 84 -> 104. Then the torso's first key turned with the hips, not
// halfway to a root joint above them (deform/posing/key_posing.h; only the child's and the heavy
// male's rigs have such a root), measured before and after on one machine: child 297 -> 225
// (its torso's 64 worse pairs gone), heavy male 360 -> 259 (its legs' 97 and 39 of its torso's
// 55), every other entry unchanged; 2,452 -> 2,279 in all.
const std::map<std::string, int> kLedger = {
    {"makehuman_male_cmu", 316},
    {"RiggedFigure", 727},
    {"makehuman_child_mixamo_unity", 225},
    {"makehuman_female_old_heavy_mixamo", 91},
    {"makehuman_female_slim_openpose", 44},
    {"makehuman_male_old_heavy_unreal", 259},
    {"mannequin:6000", 164},
    {"mannequin:20000", 217},
    {"mannequin:72000", 236},
};

// Issue 47's target "on cmu_01_01 and cmu_01_03, every corpus body's sweep keeps every edge within
// 3x its rest length", asserted for the variants where it holds at the gate's sampling (every 100th
// frame; every edge of the torso, neck, arms and legs), worst of both clips measured with one link
// key per link (stop 65): male 2.59 (mirrored 2.65, x0.6 2.59), heavy female 2.89 (mirrored 2.85,
// x0.6 2.89), RiggedFigure 1.69 (mirrored 1.68), mannequins 2.13 / 2.13 / 2.19 (6k / 20k / 72k;
// mirrored 2.08 / 2.18 / 2.17); and the child since its torso's first key turns with its hips
// (deform/posing/key_posing.h): 2.81 (mirrored 2.87, x0.6 2.81) on cmu_01_03, and on cmu_01_01
// 1.88 (mirrored 1.94) where it was 3.13 (mirrored 3.13): its hips turned 185° from rest below a
// root the clip leaves at rest, the first key turned halfway to the root the short way round, 90°
// against the chest, a band round its waist where LBS and DQS stretch nothing (frame 1200; its
// torso lost to skinning on 9 of the clip's 28 sampled frames, on none now). Not yet, printed:
// the OpenPose female (3.56 as is: the armpit's wall with an arm raised behind the head or
// crossed overhead, cmu_01_03 frames 1900 and 2100, LBS's worst edge at those frames 4.91 and
// 6.62, and every 10th frame 4.11 at frame 2010; mirrored 3.99, not looked at) and the heavy male
// (3.78, mirrored 3.78, on cmu_01_03 frame 3700, arms overhead: the torso's side wall below the
// armpit, an edge from a vertex 81 % skinned, 11 % on the arm's sweep 7 cm outside its ellipse
// (which the raised arm carries 30 cm from where skinning puts it) and 8 % torso, to one all
// skinned; LBS 1.55 on that edge, 8.19 at its worst; stop 65 read it as the belly's overhang; on
// cmu_01_01 3.40 before its first key turned with the hips, 2.25 after). The heavy female
// mirrored (4.00 before), the heavy male mirrored (3.96) and the child mirrored (4.84) were
// measured facing backwards before stop 64 (tests/mirrored_model.h did not swap their Mixamo and
// Unreal side names); the OpenPose female
// mirrored measured 3.86 before an edge between two regions counted in both.
constexpr double kCmuStretchTarget = 3.0;
const std::set<std::string> kWithinTargetOnCmu = {
    "makehuman_male_cmu", "makehuman_male_cmu mirrored", "makehuman_male_cmu x0.6",
    "makehuman_female_old_heavy_mixamo", "makehuman_female_old_heavy_mixamo mirrored",
    "makehuman_female_old_heavy_mixamo x0.6",
    "makehuman_child_mixamo_unity", "makehuman_child_mixamo_unity mirrored",
    "makehuman_child_mixamo_unity x0.6",
    "RiggedFigure", "RiggedFigure mirrored", "RiggedFigure x0.6",
    "mannequin:6000", "mannequin:6000 mirrored", "mannequin:6000 x0.6",
    "mannequin:20000", "mannequin:20000 mirrored", "mannequin:20000 x0.6",
    "mannequin:72000", "mannequin:72000 mirrored", "mannequin:72000 x0.6"};

// Where the worse pairs are, printed per body so that the largest class shows: per region, by
// cause (the stretch, flipped triangles, both) and by how far the stretch passes 1.02x the
// better baseline's (excess: sweep / (1.02 x baseline), under 1.05, 1.05-1.2, over 1.2), and per
// clip.
struct WorseBreakdown {
  static constexpr const char* kCauses[3] = {"stretch", "flips", "both"};
  static constexpr const char* kBands[3] = {"<5%", "5-20%", ">20%"};
  struct Row {
    int cause[3] = {0, 0, 0};
    int band[3] = {0, 0, 0};  // pairs worse by their stretch (alone or with flips)
    std::map<std::string, int> clip;
    std::map<std::string, int> where;  // clip and frame, or the range of motion's move
  };
  std::map<std::string, Row> region;

  void add(const char* region_name, const std::string& clip, const std::string& where,
           const SkinningComparison& c, bool extra_flips) {
    const bool stretched = c.excess > 1.0;
    Row& row = region[region_name];
    ++row.cause[stretched && extra_flips ? 2 : extra_flips ? 1 : 0];
    if (stretched) ++row.band[c.excess <= 1.05 ? 0 : c.excess <= 1.2 ? 1 : 2];
    ++row.clip[clip];
    ++row.where[where];
  }
  void print(const std::string& body) const {
    for (const auto& [name, row] : region) {
      std::printf("%s breakdown %-10s", body.c_str(), name.c_str());
      for (int i = 0; i < 3; ++i) std::printf(" %s %3d", kCauses[i], row.cause[i]);
      std::printf(" |");
      for (int i = 0; i < 3; ++i) std::printf(" %s %3d", kBands[i], row.band[i]);
      std::printf(" |");
      for (const auto& [clip, n] : row.clip) std::printf(" %s %3d", clip.c_str(), n);
      std::vector<std::pair<int, std::string>> most;
      for (const auto& [where, n] : row.where) most.push_back({-n, where});
      std::sort(most.begin(), most.end());
      std::printf(" | most:");
      for (std::size_t i = 0; i < std::min<std::size_t>(4, most.size()); ++i)
        std::printf(" %s (%d)", most[i].second.c_str(), -most[i].first);
      std::printf("\n");
    }
  }
};

struct ClipCount {
  int worse = 0, frames = 0;
  // Per method, over every frame: the worst stretch of the torso, neck, arms and legs, every
  // edge of them (so that handing a region to skinning does not hide what it loses there).
  double worst[3] = {1.0, 1.0, 1.0};
};

bool swept_part(deform::BodyPart part) {
  using deform::BodyPart;
  return part == BodyPart::kTorso || part == BodyPart::kNeck || part == BodyPart::kLeftArm ||
         part == BodyPart::kRightArm || part == BodyPart::kLeftLeg || part == BodyPart::kRightLeg;
}

// poses[i] is named names[i]: its move, or its clip frame.
ClipCount measure(const deform::BoundModel& bound, const std::vector<deform::Pose>& poses,
                  const std::vector<std::string>& names, const std::string& clip,
                  WorseBreakdown& breakdown) {
  deform::test::Posing posing(bound);
  const RegionMeter meter(bound);
  std::vector<glm::vec3> positions(bound.model.vertex_count());
  ClipCount count;
  for (std::size_t p = 0; p < poses.size(); ++p) {
    deform::Pose pose = poses[p];  // Posing::deform takes it mutable
    std::vector<RegionFigures> figures[3];
    for (int m = 0; m < 3; ++m) {
      posing.deform(pose, static_cast<DeformMethod>(m), positions);
      figures[m] = meter.measure(positions, posing.world_pose());
      for (std::size_t r = 0; r < figures[m].size(); ++r)
        if (swept_part(meter.regions()[r]))
          count.worst[m] = std::max(count.worst[m], figures[m][r].stretch);
    }
    for (std::size_t r = 0; r < figures[0].size(); ++r) {
      const SkinningComparison c =
          compare_with_skinning(figures[0][r], figures[1][r], figures[2][r]);
      if (!c.worse) continue;
      ++count.worse;
      const bool extra_flips = figures[0][r].swept_flipped >
                               std::min(figures[1][r].swept_flipped, figures[2][r].swept_flipped);
      breakdown.add(deform::to_string(meter.regions()[r]), clip, names[p], c, extra_flips);
    }
    ++count.frames;
  }
  return count;
}

class CorpusGate : public testing::TestWithParam<std::string> {};

TEST_P(CorpusGate, TheSweepIsWorseThanSkinningNowhereNewAndKeepsItsAdvantage) {
  const std::string file = GetParam();
  const fs::path data(SWEEPD_SHARED_DATA);
  if (!fs::exists(data / "motion/cmu_01_01.bvh")) GTEST_SKIP() << "shared data absent";
  // "mannequin:N": the procedural mannequin of about N vertices; else a shared model file.
  const bool procedural = file.starts_with("mannequin:");
  if (!procedural && !fs::exists(data / file)) GTEST_SKIP() << "shared data absent: " << file;
  const std::string body = procedural ? file : fs::path(file).stem().string();
  const deform::Model model =
      procedural ? mannequin::make_mannequin({.target_vertices = std::stoi(file.substr(10))})
                 : io::load_gltf(data / file);
  // The better baseline's worst over the sweep's, at least: 1.05 on the MakeHuman bodies (the
  // least measured 1.09, the OpenPose body mirrored on cmu_01_03: 10.11 against 10.97), so that
  // a crotch or an armpit handed to skinning fails; within the gate's 2 % on the low-poly
  // RiggedFigure, whose skin every method stretches alike (mirrored, on cmu_01_03: 1.67 against
  // 1.71).
  const double advantage = body == "RiggedFigure" ? 1.0 / kSkinningTolerance : 1.05;
  int worse = 0;
  WorseBreakdown breakdown;
  for (const test_models::BodyVariant& variant :
       test_models::plain_mirrored_and_rescaled({{body, &model}}, 0.6f)) {
    // Bound as sweepctl bind and sweepd bind it: adapted where the self-check finds a refit
    // that wins (selfcheck::adapt_binding).
    const deform::BoundModel bound =
        selfcheck::bind_checked(variant.model, deform::detect_rig_map(variant.model.skeleton),
                                {}, true)
            .bound;
    struct NamedPoses {
      std::string clip;
      std::vector<deform::Pose> poses;
      std::vector<std::string> names;  // the move, or the clip's frame
    };
    std::vector<NamedPoses> clips;
    const motion::RangeOfMotion rom = motion::range_of_motion(variant.model.skeleton, bound.rig);
    const motion::OwnSkeletonClip rom_player(rom.clip, variant.model.skeleton);
    clips.push_back({"range of motion", {}, {}});
    for (const motion::RomMove& move : rom.moves) {
      clips.back().poses.push_back(rom_player.pose_at_frame(move.peak_frame));
      clips.back().names.push_back(move.name);
    }
    for (const char* name : {"cmu_01_01", "cmu_01_03"}) {
      const motion::Retargeter clip(io::load_bvh(data / "motion" / (std::string(name) + ".bvh")),
                                    variant.model);
      clips.push_back({name, {}, {}});
      for (int f = 0; f < clip.frame_count(); f += kClipStep) {
        clips.back().poses.push_back(clip.pose_at_frame(f));
        clips.back().names.push_back(std::string(name) + "@" + std::to_string(f));
      }
    }
    for (const auto& [clip, poses, names] : clips) {
      const ClipCount count = measure(bound, poses, names, clip, breakdown);
      std::printf("%-40s %-16s worse in %3d (frame, region) pairs of %3d frames; worst stretch "
                  "sweep %.2f, lbs %.2f, dqs %.2f\n",
                  variant.name.c_str(), clip.c_str(), count.worse, count.frames, count.worst[0],
                  count.worst[1], count.worst[2]);
      worse += count.worse;
      EXPECT_LE(count.worst[0] * advantage, std::min(count.worst[1], count.worst[2]))
          << variant.name << " " << clip << ": the sweep's worst limb or torso edge against skinning's";
      if (clip != "range of motion" && kWithinTargetOnCmu.contains(variant.name)) {
        EXPECT_LE(count.worst[0], kCmuStretchTarget)
            << variant.name << " " << clip << ": an edge stretched past 3x its rest length";
      }
    }
  }
  breakdown.print(body);
  std::printf("%s: worse than skinning in %d (frame, region) pairs (ledger %d, target 0)\n",
              body.c_str(), worse, kLedger.at(body));
  // 2 % over the ledger: pairs within float rounding of the 1.02 threshold may fall either way
  // on another CPU (the sweep's AVX2 and SSE2 loops round differently).
  EXPECT_LE(worse, kLedger.at(body) + kLedger.at(body) / 50)
      << body << ": worse than skinning somewhere new";
}

INSTANTIATE_TEST_SUITE_P(
    SharedBodies, CorpusGate,
    testing::Values("models/makehuman_male_cmu.glb", "models/RiggedFigure/RiggedFigure.gltf",
                    "models/corpus/makehuman_child_mixamo_unity.glb",
                    "models/corpus/makehuman_female_old_heavy_mixamo.glb",
                    "models/corpus/makehuman_female_slim_openpose.glb",
                    "models/corpus/makehuman_male_old_heavy_unreal.glb", "mannequin:6000",
                    "mannequin:20000", "mannequin:72000"),
    [](const testing::TestParamInfo<std::string>& info) {
      std::string name = fs::path(info.param).stem().string();
      std::replace(name.begin(), name.end(), ':', '_');
      return name;
    });

}  // namespace
}  // namespace sweepd::metrics
