// A lying body rests on the floor though the clip pushes an arm through its own (issue 48 item
// 3, motion/clip_arms_through_floor.h and motion/body_floor.h). Clip: cmu_01_01 knocked down
// forwards (tests/motion/knocked_down_clip.h: from frame 300 the body lies face down while its
// arms go on swinging as in the walk, through the clip's floor by up to 22 cm). Bodies: the
// shared male (also mirrored), the four corpus bodies, the RiggedFigure and the mannequin.
// Frames: every 10th from 300 on where a clip arm joint (shoulder, elbow, wrist, hand) lies
// below the clip's floor (found here from the clip's own joints). Figure, per frame: the
// torso's rest gap, the lowest vertex of the swept mesh whose strongest influence is a torso,
// neck or head joint (BodyContacts' back and hips) above the floor (the rest mesh's lowest
// vertex). Asserted: the torso rests on every such frame, within a part's contact height of
// the floor (motion/body_contacts.h: 0.035 L, 2.5-3.5 cm; the body floor keeps the torso's
// samples 0.5 cm up, and the swept surface lies up to about 1.5 cm off their estimate).
// Before (the arm held the body up) 6-16 cm at worst per body; measured after 0.5-2.1 cm (the
// slim female 2.05 cm at frame 420, where the clip's arm comes back up out of its floor). And
// the swept body's lowest vertex on every 10th frame of the clip at or above -1 cm (the
// issue's target; measured -0.58 to 0.00 cm).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "deform/binding/bind.h"
#include "io/bvh/bvh_load.h"
#include "motion/body_contacts.h"
#include "motion/retarget.h"
#include "tests/deform/shared_male.h"
#include "tests/motion/clip_world_positions.h"
#include "tests/motion/floor_figures.h"
#include "tests/motion/knocked_down_clip.h"
#include "tests/motion/test_bodies.h"

namespace sweepd::motion {
namespace {

using test_models::Body;

// Whether a clip joint of an arm (CMU's names: *Arm, *ForeArm, *Hand, fingers) lies below
// the clip's floor (y = 0) on the frame.
bool clip_arm_through_floor(const Clip& clip, int frame) {
  const std::vector<glm::vec3> position = clip_world_positions(clip, frame);
  for (std::size_t j = 0; j < clip.joints.size(); ++j) {
    const std::string& name = clip.joints[j].name;
    const bool arm =
        name.find("Arm") != std::string::npos || name.find("Hand") != std::string::npos;
    if (arm && position[j].y < 0.0f) return true;
  }
  return false;
}

class LyingBody : public ::testing::TestWithParam<Body> {};

TEST_P(LyingBody, TheTorsoRestsWhereTheClipPushesAnArmThroughItsFloor) {
  const std::optional<deform::Model> body = test_models::load_body(GetParam());
  if (!body) GTEST_SKIP() << "shared data absent: " << GetParam().file;
  const deform::Model& model = *body;
  const deform::RigMap map = deform::detect_rig_map(model.skeleton);
  const deform::BoundModel bound = deform::bind(model, map);
  const Clip clip = test_clips::knocked_down(
      io::load_bvh(std::filesystem::path(SWEEPD_SHARED_DATA) / "motion/cmu_01_01.bvh"), 90.0f);
  const Retargeter retargeter(clip, model);
  const std::vector<int> part = BodyContacts::part_of_joints(map, model.skeleton);
  std::vector<bool> torso(model.vertex_count());
  for (std::size_t v = 0; v < torso.size(); ++v) {
    const auto& w = model.skin_weights[v];
    const int strongest = static_cast<int>(std::max_element(w.begin(), w.end()) - w.begin());
    const int p = part[model.skin_joints[v][strongest]];
    torso[v] = p == BodyContacts::kBack || p == BodyContacts::kHips;
  }
  deform::test::Posing posing(bound);
  std::vector<glm::vec3> positions(model.vertex_count());
  const float floor = test::lowest(model.positions);
  const float resting = BodyContacts::kPartContactHeight * retargeter.model_hip_height();
  float worst_gap = 0.0f;
  int worst_frame = -1, frames = 0;
  for (int f = 300; f < clip.frame_count; f += 10) {
    if (!clip_arm_through_floor(clip, f)) continue;
    deform::Pose pose = retargeter.pose_at_frame(f);
    posing.deform(pose, deform::DeformMethod::kSweep, positions);
    float gap = std::numeric_limits<float>::infinity();
    for (std::size_t v = 0; v < positions.size(); ++v)
      if (torso[v]) gap = std::min(gap, positions[v].y - floor);
    ++frames;
    EXPECT_LE(gap, resting) << "frame " << f;
    if (gap > worst_gap) worst_gap = gap, worst_frame = f;
  }
  const float lowest = test::lowest_over_clip(bound, retargeter);
  std::printf(
      "%s%s: %d frames with an arm through the clip's floor, torso rest gap at most "
      "%.2f cm (frame %d); lowest vertex %.2f cm\n",
      GetParam().file, GetParam().mirror ? " mirrored" : "", frames, 100 * worst_gap, worst_frame,
      100 * lowest);
  EXPECT_GT(frames, 5) << "the knocked-down clip should push an arm through its floor";
  EXPECT_GE(lowest, -0.01f);
}

INSTANTIATE_TEST_SUITE_P(Bodies, LyingBody, ::testing::ValuesIn(test_models::every_body(true)),
                         [](const ::testing::TestParamInfo<Body>& info) {
                           return test_models::body_test_name(info.param);
                         });

}  // namespace
}  // namespace sweepd::motion
