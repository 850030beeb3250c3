// The feet of the shared male on the CMU clips' frames where the clip curls its toes furthest:
// the skin at the ball of the foot stays within issue 4's bound of 3x its rest edge lengths.
// The clip's toe channels curled the male's toes up to 61° (through the floor, with one-frame
// jumps of up to 60°) and stretched the toe crease 4.09x (cmu_01_03 frames 2379 and 3517, equal
// with LBS: the feet are skinned); motion::Retargeter no longer drives the clip's toes (see
// motion/retarget.h). Printed for comparison: LBS, and the toes driven again by a name map.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "deform/job/deform_job.h"
#include "io/bvh/bvh_load.h"
#include "motion/retarget.h"
#include "tests/deform/shared_male.h"

namespace sweepd::deform::foot_stretch_test {
namespace {

namespace fs = std::filesystem;

struct FootEdge {
  std::uint32_t a, b;
  float rest_length;
};

// Part of the joint that weighs most on vertex v.
BodyPart heaviest_part(const Model& model, std::span<const BodyPart> joint_part, std::uint32_t v) {
  int heaviest = 0;
  for (int i = 1; i < kInfluences; ++i)
    if (model.skin_weights[v][i] > model.skin_weights[v][heaviest]) heaviest = i;
  return joint_part[model.skin_joints[v][heaviest]];
}

// Every triangle edge with an end on a foot (each edge once per triangle side: a repeat does not
// change the largest stretch).
std::vector<FootEdge> foot_edges(const BoundModel& bound) {
  const Model& model = bound.model;
  const std::vector<BodyPart> joint_part = label_joints(bound.rig, model.skeleton);
  const auto on_foot = [&](std::uint32_t v) {
    const BodyPart part = heaviest_part(model, joint_part, v);
    return part == BodyPart::kLeftFoot || part == BodyPart::kRightFoot;
  };
  std::vector<FootEdge> edges;
  for (std::size_t t = 0; t < model.indices.size(); t += 3)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = model.indices[t + k], b = model.indices[t + (k + 1) % 3];
      const float length = glm::distance(model.positions[a], model.positions[b]);
      if ((on_foot(a) || on_foot(b)) && length > 0.0f) edges.push_back({a, b, length});
    }
  return edges;
}

float largest_stretch(std::span<const FootEdge> edges, std::span<const glm::vec3> positions) {
  float largest = 0.0f;
  for (const FootEdge& e : edges)
    largest = std::max(largest, glm::distance(positions[e.a], positions[e.b]) / e.rest_length);
  return largest;
}

TEST(FootStretch, TheToeCreaseStaysWithinThreeTimesItsRestLengthWhereTheClipCurlsTheToes) {
  REQUIRE_SHARED_MALE();
  const fs::path data(SWEEPD_SHARED_DATA);
  const motion::JointNameMap toes_driven{
      .source = "toes driven",
      .pairs = {{"LeftToeBase", "LeftToeBase"}, {"RightToeBase", "RightToeBase"}}};
  test::Posing deformer(male);
  const std::vector<FootEdge> edges = foot_edges(male);
  std::vector<glm::vec3> positions(male.model.vertex_count());
  struct Case {
    const char* clip;
    int frame;  // where the clip's toe channels stretched a foot most (left, then right)
  };
  // 25 frames either side (0.2 s): the curl is held 20-25 frames.
  constexpr int kAround = 25;
  for (const Case& c : {Case{"motion/cmu_01_03.bvh", 2379}, Case{"motion/cmu_01_03.bvh", 3517},
                        Case{"motion/cmu_01_01.bvh", 1090}, Case{"motion/cmu_01_01.bvh", 598}}) {
    const motion::Clip motion = io::load_bvh(data / c.clip);
    const motion::Retargeter retargeter(motion, male.model);
    const motion::Retargeter driven(motion, male.model, toes_driven);
    float sweep = 0.0f, lbs = 0.0f, lbs_toes_driven = 0.0f;
    for (int frame = c.frame - kAround; frame <= c.frame + kAround; ++frame) {
      Pose pose = retargeter.pose_at_frame(frame);
      deformer.deform(pose, DeformMethod::kSweep, positions, {});
      sweep = std::max(sweep, largest_stretch(edges, positions));
      deformer.deform(pose, DeformMethod::kLbs, positions, {});
      lbs = std::max(lbs, largest_stretch(edges, positions));
      Pose toes_curled = driven.pose_at_frame(frame);
      deformer.deform(toes_curled, DeformMethod::kLbs, positions, {});
      lbs_toes_driven = std::max(lbs_toes_driven, largest_stretch(edges, positions));
    }
    std::printf(
        "%s frames %d-%d: largest foot edge stretch %.2fx sweep | %.2fx lbs | %.2fx lbs "
        "with the clip's toes driven\n",
        c.clip, c.frame - kAround, c.frame + kAround, sweep, lbs, lbs_toes_driven);
    // Issue 4's bound: no edge longer than 3x its rest length. The feet move with the male's
    // painted weights and the toes with the foot; what stretches most now are sub-millimetre
    // edges on the toes whose painted weights carry a stray shin or other-foot influence (1-2%).
    EXPECT_LE(sweep, 3.0f) << c.clip << " around frame " << c.frame;
  }
}

}  // namespace
}  // namespace sweepd::deform::foot_stretch_test
