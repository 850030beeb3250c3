// Tests for motion::Retargeter: CMU clip cmu_01_01.bvh (T-pose rest) on the shared MakeHuman male
// (A-pose rest), both from ../shared/data.
#include "motion/retarget.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "deform/baselines/linear_blend_skinning.h"
#include "deform/model/forward_kinematics.h"
#include "io/bvh/bvh_load.h"
#include "io/gltf/gltf_load.h"
#include "mannequin/mannequin.h"
#include "tests/motion/clip_world_positions.h"

namespace sweepd::motion::retarget_test {
namespace {

namespace fs = std::filesystem;
using io::load_bvh;
using io::load_gltf;

const fs::path kData = SWEEPD_SHARED_DATA;
const fs::path kMale = kData / "models" / "makehuman_male_cmu.glb";
const fs::path kClip = kData / "motion" / "cmu_01_01.bvh";
constexpr float kCmuUnit = 0.056444f;  // metres per CMU BVH unit

// Bones (joint, child) that exist under these names in both the clip and the model.
const std::pair<const char*, const char*> kLimbBones[] = {
    {"LeftArm", "LeftForeArm"},    {"LeftForeArm", "LeftHand"}, {"RightArm", "RightForeArm"},
    {"RightForeArm", "RightHand"}, {"LeftUpLeg", "LeftLeg"},    {"LeftLeg", "LeftFoot"},
    {"RightUpLeg", "RightLeg"},    {"RightLeg", "RightFoot"},   {"LeftFoot", "LeftToeBase"},
    {"RightFoot", "RightToeBase"}, {"LowerBack", "Spine"},      {"Spine", "Spine1"}};

float angle_degrees(const glm::vec3& a, const glm::vec3& b) {
  return glm::degrees(
      std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0f, 1.0f)));
}

class RetargetTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(kMale) || !fs::exists(kClip))
      GTEST_SKIP() << "shared data absent: " << kMale << " or " << kClip;
    model_ = load_gltf(kMale);
    motion_ = load_bvh(kClip, {.length_scale = kCmuUnit});
  }

  // World joint positions of the model in a pose.
  std::vector<glm::vec3> model_positions(const deform::Pose& pose) const {
    std::vector<glm::mat4> world(model_.skeleton.joints.size());
    deform::forward_kinematics(model_.skeleton, pose, world);
    std::vector<glm::vec3> positions;
    for (const glm::mat4& m : world) positions.emplace_back(m[3]);
    return positions;
  }

  // World joint positions of the clip at a frame, by its own forward kinematics.
  std::vector<glm::vec3> clip_positions(int frame) const {
    return clip_world_positions(motion_, frame);
  }

  int model_joint(const char* name) const { return model_.skeleton.find(name); }

  // At a few frames, the model's limb and spine bones point where the clip's bones point.
  // The retargeted rotations, before foot planting bends the legs where the clip plants a foot
  // (Feet::kPlanted, the default; tests/motion/foot_planting_test.cpp).
  void expect_bones_follow_the_clip() const {
    const Retargeter retargeter(motion_, model_, {}, Feet::kFree);
    float worst = 0.0f;
    for (int frame : {1, 400, 900, 1377, 2000, motion_.frame_count - 1}) {
      deform::Pose pose = retargeter.pose_at_frame(frame);
      ASSERT_EQ(deform::normalize_and_validate(pose, model_.skeleton), "") << "frame " << frame;
      const std::vector<glm::vec3> model = model_positions(pose);
      const std::vector<glm::vec3> clip = clip_positions(frame);
      for (const auto& [joint, child] : kLimbBones) {
        const float angle = angle_degrees(model[model_joint(child)] - model[model_joint(joint)],
                                          clip[motion_.find(child)] - clip[motion_.find(joint)]);
        // Retargeting aligns each bone exactly; 2° leaves room for float round-off along
        // chains of up to 8 joints and is still far below a visible error.
        EXPECT_LT(angle, 2.0f) << joint << " -> " << child << " at frame " << frame;
        worst = std::max(worst, angle);
      }
    }
    std::printf("%s: largest bone direction difference %.4f degrees\n", model_.name.c_str(), worst);
  }

  deform::Model model_;
  Clip motion_;
};

TEST_F(RetargetTest, MapsEveryJointButTheFingersAndThumbs) {
  const Retargeter retargeter(motion_, model_);
  // The clip's joints below its hands are not measured (see the header): left out, and the
  // model's fingers and thumbs keep their rest rotation relative to the hand.
  const std::vector<std::string> hands = {"LeftFingerBase",  "LFingers", "LThumb",
                                          "RightFingerBase", "RFingers", "RThumb"};
  EXPECT_EQ(retargeter.unmapped_bvh_joints(), hands);
  EXPECT_EQ(retargeter.unmapped_model_joints(),
            (std::vector<std::string>{"LThumb", "LeftFingerBase", "LeftHandFinger1", "RThumb",
                                      "RightFingerBase", "RightHandFinger1"}));
  EXPECT_EQ(retargeter.matches().size(), 25u);
  // The fingers, the toes, then the model joints left without motion: its fingers and toes.
  ASSERT_EQ(retargeter.warnings().size(), 3u);
  EXPECT_NE(retargeter.warnings()[0].find("LThumb"), std::string::npos);
  EXPECT_EQ(retargeter.warnings()[2],
            "model joints the clip leaves without motion, at their rest rotation (8): LThumb, "
            "LeftFingerBase, LeftHandFinger1, RThumb, RightFingerBase, RightHandFinger1, "
            "LeftToeBase, RightToeBase");
  // Every frame: the model's thumb and finger base turn exactly as its hand does.
  const deform::Pose pose = retargeter.pose_at_frame(1300);
  for (const char* joint : {"LThumb", "LeftFingerBase", "RThumb", "RightFingerBase"}) {
    const int m = model_joint(joint);
    EXPECT_EQ(pose.local_rotations[m], model_.skeleton.joints[m].rest_rotation) << joint;
  }
}

// The model's toe of each side: matched to the clip's (so the foot bone above still points
// where the clip's foot points, see kLimbBones) and kept at its rest rotation.
void expect_toes_paired_but_undriven(const Retargeter& retargeter, const deform::Skeleton& model,
                                     const std::vector<std::string>& driven_toes) {
  for (const char* toe : {"LeftToeBase", "RightToeBase"}) {
    const int m = model.find(toe);
    const auto found =
        std::find_if(retargeter.matches().begin(), retargeter.matches().end(),
                     [&](const JointMatch& match) { return match.model_joint == m; });
    ASSERT_NE(found, retargeter.matches().end()) << toe;
    const bool driven = std::find(driven_toes.begin(), driven_toes.end(), toe) != driven_toes.end();
    EXPECT_EQ(found->driven, driven) << toe;
    // Frames where the clip turns the left toe 32° (1090) and the right toe 36° (598).
    for (int frame : {598, 1090}) {
      const deform::Pose pose = retargeter.pose_at_frame(frame);
      EXPECT_EQ(pose.local_rotations[m] == model.joints[m].rest_rotation, !driven)
          << toe << " at frame " << frame;
    }
  }
}

TEST_F(RetargetTest, ToesAimTheFootButAreNotDriven) {
  const Retargeter retargeter(motion_, model_);
  expect_toes_paired_but_undriven(retargeter, model_.skeleton, {});
  ASSERT_EQ(retargeter.warnings().size(), 3u);  // the fingers, the toes, the joints left still
  EXPECT_NE(retargeter.warnings()[1].find("toes are not driven (LeftToeBase, RightToeBase)"),
            std::string::npos)
      << retargeter.warnings()[1];
}

TEST_F(RetargetTest, LimbBonesPointWhereTheClipsBonesPoint) { expect_bones_follow_the_clip(); }

TEST_F(RetargetTest, MannequinLimbBonesPointWhereTheClipsBonesPoint) {
  model_ = mannequin::make_mannequin({.target_vertices = 2000});  // only its skeleton matters
  expect_bones_follow_the_clip();
}

TEST_F(RetargetTest, ArmsAreHorizontalAtTheClipsRestPose) {
  const Retargeter retargeter(motion_, model_);
  const std::vector<glm::vec3> rest = model_positions(deform::rest_pose(model_.skeleton));
  const std::vector<glm::vec3> t_pose = model_positions(retargeter.pose_at_bvh_rest());
  for (const auto& [joint, child] :
       {std::pair{"LeftArm", "LeftForeArm"}, std::pair{"LeftForeArm", "LeftHand"},
        std::pair{"RightArm", "RightForeArm"}, std::pair{"RightForeArm", "RightHand"}}) {
    const glm::vec3 rest_bone = rest[model_joint(child)] - rest[model_joint(joint)];
    const glm::vec3 bone = t_pose[model_joint(child)] - t_pose[model_joint(joint)];
    const glm::vec3 horizontal(bone.x, 0.0f, bone.z);
    // The model rests in an A-pose (arms well below horizontal), so this can fail.
    EXPECT_GT(angle_degrees(rest_bone, glm::vec3(rest_bone.x, 0.0f, rest_bone.z)), 20.0f) << joint;
    // The clip's rest is a T-pose with level arms; same 2° as the bone test above.
    EXPECT_LT(angle_degrees(bone, horizontal), 2.0f) << joint << " -> " << child;
  }
}

TEST_F(RetargetTest, RootTranslationIsScaledByTheHipHeightRatio) {
  // Free feet: the root exactly where the scale puts it (planting may bring the body down).
  const Retargeter retargeter(motion_, model_, {}, Feet::kFree);
  // Expected ratio, measured here: pelvis height above the floor on straight legs = drop to the
  // hip joint + thigh + shin (mean of both legs) + ankle height: the model's in its rest pose,
  // the clip's as it stands (the 10th percentile of its lower ankle's height above y = 0 over
  // its frames; CMU's rest skeleton has no heel, so its rest ankle stands 2.4 cm above its toes).
  const std::vector<glm::vec3> model_rest = model_positions(deform::rest_pose(model_.skeleton));
  float model_floor = model_.positions[0].y;
  for (const glm::vec3& p : model_.positions) model_floor = std::min(model_floor, p.y);
  std::vector<glm::vec3> clip_rest(motion_.joints.size());
  for (std::size_t b = 0; b < motion_.joints.size(); ++b) {
    const int parent = motion_.joints[b].parent;
    clip_rest[b] = (parent < 0 ? glm::vec3(0.0f) : clip_rest[parent]) + motion_.joints[b].offset;
  }
  const auto legs = [](const std::vector<glm::vec3>& p, int pelvis, std::array<int, 3> left,
                       std::array<int, 3> right) {
    float sum = 0.0f;
    for (const auto& [hip, knee, ankle] : {left, right})
      sum += p[pelvis].y - p[hip].y + glm::distance(p[hip], p[knee]) +
             glm::distance(p[knee], p[ankle]);
    return sum / 2.0f;
  };
  const std::array<int, 3> model_left = {model_joint("LeftUpLeg"), model_joint("LeftLeg"),
                                         model_joint("LeftFoot")};
  const std::array<int, 3> model_right = {model_joint("RightUpLeg"), model_joint("RightLeg"),
                                          model_joint("RightFoot")};
  const float model_height = legs(model_rest, model_joint("Hips"), model_left, model_right) +
                             (model_rest[model_left[2]].y + model_rest[model_right[2]].y) / 2.0f -
                             model_floor;
  const int left_ankle = motion_.find("LeftFoot"), right_ankle = motion_.find("RightFoot");
  std::vector<float> lower_ankle;
  for (int frame = 0; frame < motion_.frame_count; ++frame) {
    const std::vector<glm::vec3> p = clip_positions(frame);
    lower_ankle.push_back(std::min(p[left_ankle].y, p[right_ankle].y));
  }
  std::sort(lower_ankle.begin(), lower_ankle.end());
  const float stance_ankle = lower_ankle[lower_ankle.size() / 10];
  const float clip_height =
      legs(clip_rest, motion_.find("Hips"),
           {motion_.find("LeftUpLeg"), motion_.find("LeftLeg"), left_ankle},
           {motion_.find("RightUpLeg"), motion_.find("RightLeg"), right_ankle}) +
      stance_ankle;
  std::printf("hip heights: model %.4f m, clip %.4f m (its ankles stand %.4f m high)\n",
              model_height, clip_height, stance_ankle);
  // CMU's subject stands with flat feet: ankles 8-11 cm up.
  EXPECT_GT(stance_ankle, 0.08f);
  EXPECT_LT(stance_ankle, 0.11f);
  // Sums of a few float distances: relative round-off.
  EXPECT_NEAR(retargeter.root_scale(), model_height / clip_height, 1e-5f);
  const Retargeter planted(motion_, model_);
  EXPECT_EQ(planted.root_scale(), retargeter.root_scale());
  for (int frame : {0, 700, 2100}) {
    const glm::vec3 hips = model_positions(retargeter.pose_at_frame(frame))[model_joint("Hips")];
    const glm::vec3 clip_hips = clip_positions(frame)[motion_.find("Hips")];
    // Hips is the model's root: its position is the scaled clip position; float round-off.
    EXPECT_LT(glm::distance(hips, retargeter.root_scale() * clip_hips), 1e-5f) << "frame " << frame;
    // Scaled so, the standing body's feet reach the floor: planting brings it down by at most
    // 1 cm (it came down 4.4-5.0 cm with the clip's rest ankle height, which hid behind the hip
    // links' alignment before they kept their rest angle) and never moves it sideways.
    const glm::vec3 planted_hips =
        model_positions(planted.pose_at_frame(frame))[model_joint("Hips")];
    std::printf("frame %d: planting moves the hips %.4f m\n", frame, planted_hips.y - hips.y);
    EXPECT_LE(planted_hips.y, hips.y + 1e-5f) << "frame " << frame;
    EXPECT_GT(planted_hips.y, hips.y - 0.01f) << "frame " << frame;
    EXPECT_LT(glm::length(glm::vec2(planted_hips.x - hips.x, planted_hips.z - hips.z)), 1e-5f);
  }
}

// A clip whose feet never come near y = 0 (here cmu_01_01 lifted 2 m: a floor elsewhere) has
// no stance to measure: its ankles are measured in its rest pose, and a warning says so.
TEST_F(RetargetTest, AClipWhoseFeetNeverNearTheFloorMeasuresItsAnklesAtRest) {
  const Retargeter on_the_floor(motion_, model_, {}, Feet::kFree);
  Clip lifted = motion_;
  const ClipJoint& root = lifted.joints[0];
  int y = -1;
  for (std::size_t c = 0; c < root.channels.size(); ++c)
    if (root.channels[c] == Channel::kYposition) y = root.channel_offset + static_cast<int>(c);
  ASSERT_GE(y, 0) << "CMU's root has a Y position channel";
  for (int frame = 0; frame < lifted.frame_count; ++frame)
    lifted.values[static_cast<std::size_t>(frame) * lifted.channel_count + y] += 2.0f;
  const Retargeter retargeter(lifted, model_, {}, Feet::kFree);
  // The fingers, the toes, the model joints left without motion, then this.
  ASSERT_EQ(retargeter.warnings().size(), 4u);
  EXPECT_NE(retargeter.warnings()[3].find("do not stand near its floor"), std::string::npos)
      << retargeter.warnings()[3];
  // CMU's rest ankle, 2.4 cm above its toes, against its 10 cm stance: a hip height 7.6 cm
  // lower, a scale about 8 % larger.
  const float ratio = retargeter.root_scale() / on_the_floor.root_scale();
  std::printf("root scale %.4f lifted, %.4f on the floor\n", retargeter.root_scale(),
              on_the_floor.root_scale());
  EXPECT_GT(ratio, 1.05f);
  EXPECT_LT(ratio, 1.11f);
}

TEST_F(RetargetTest, FeetStayOnTheFloorWhileTheClipStands) {
  const Retargeter retargeter(motion_, model_);
  const std::vector<glm::mat4> rest_inverse = deform::world_rest_inverse_matrices(model_.skeleton);
  std::vector<glm::mat4> world(model_.skeleton.joints.size()), skinning(world.size());
  std::vector<glm::vec3> positions(model_.vertex_count());
  float floor = model_.positions[0].y;
  for (const glm::vec3& p : model_.positions) floor = std::min(floor, p.y);
  for (int frame : {1, 100}) {  // the subject stands still before the first hop
    deform::forward_kinematics(model_.skeleton, retargeter.pose_at_frame(frame), world);
    deform::skinning_matrices(world, rest_inverse, skinning);
    deform::linear_blend_skinning(model_, skinning, positions, {});
    float lowest = positions[0].y;
    for (const glm::vec3& p : positions) lowest = std::min(lowest, p.y);
    std::printf("frame %d: lowest vertex %.4f m above the rest floor\n", frame, lowest - floor);
    // 3 cm: the clip measures its floor at the toe End Sites (bone centres, not soles), and
    // standing mocap sways; a wrong hip-height ratio lifts or sinks the feet by more.
    EXPECT_NEAR(lowest, floor, 0.03f) << "frame " << frame;
  }
}

TEST_F(RetargetTest, EveryFrameOfBothClipsIsAFinitePose) {
  for (const char* clip : {"cmu_01_01.bvh", "cmu_01_03.bvh"}) {
    const Retargeter retargeter(load_bvh(kData / "motion" / clip, {.length_scale = kCmuUnit}),
                                model_);
    std::vector<glm::mat4> world(model_.skeleton.joints.size());
    for (int frame = 0; frame < retargeter.frame_count(); ++frame) {
      deform::Pose pose = retargeter.pose_at_frame(frame);
      // Validation refuses NaN/Inf and zero quaternions; the FK result must be finite too.
      ASSERT_EQ(deform::normalize_and_validate(pose, model_.skeleton), "") << clip << " " << frame;
      deform::forward_kinematics(model_.skeleton, pose, world);
      for (const glm::mat4& m : world)
        for (int c = 0; c < 4; ++c)
          for (int r = 0; r < 4; ++r) ASSERT_TRUE(std::isfinite(m[c][r])) << clip << " " << frame;
    }
  }
}

TEST_F(RetargetTest, LbsSkinnedFramesOfBothClipsAreFinite) {
  const std::vector<glm::mat4> rest_inverse = deform::world_rest_inverse_matrices(model_.skeleton);
  std::vector<glm::mat4> world(model_.skeleton.joints.size()), skinning(world.size());
  std::vector<glm::vec3> positions(model_.vertex_count());
  for (const char* clip : {"cmu_01_01.bvh", "cmu_01_03.bvh"}) {
    const Retargeter retargeter(load_bvh(kData / "motion" / clip, {.length_scale = kCmuUnit}),
                                model_);
    float worst = 0.0f;
    for (int frame = 0; frame < retargeter.frame_count(); frame += 10) {  // every 12th of a second
      deform::forward_kinematics(model_.skeleton, retargeter.pose_at_frame(frame), world);
      deform::skinning_matrices(world, rest_inverse, skinning);
      deform::linear_blend_skinning(model_, skinning, positions, {});
      for (std::size_t t = 0; t < model_.indices.size(); t += 3)
        for (int k = 0; k < 3; ++k) {
          const std::uint32_t a = model_.indices[t + k], b = model_.indices[t + (k + 1) % 3];
          const float posed = glm::distance(positions[a], positions[b]);
          ASSERT_TRUE(std::isfinite(posed)) << clip << " frame " << frame;
          worst = std::max(worst, posed / glm::distance(model_.positions[a], model_.positions[b]));
        }
    }
    // Reported, not bounded: with LBS the crotch, the neck and the toes stretch short edges
    // several times over (tests/deform/posing/clip_deformation_test.cpp bounds the sweep method).
    std::printf("%s: longest LBS edge / rest length %.2f\n", clip, worst);
  }
}

// Largest rotation angle (radians) between the two poses' joint rotations. From the chord
// between the quaternions rather than acos of their dot product, which loses precision near 0.
float largest_rotation_difference(const deform::Pose& a, const deform::Pose& b) {
  float largest = 0.0f;
  for (std::size_t j = 0; j < a.local_rotations.size(); ++j) {
    const glm::quat& p = a.local_rotations[j];
    const glm::quat& q = b.local_rotations[j];
    const float chord = std::min(glm::length(p - q), glm::length(p + q));
    largest = std::max(largest, 4.0f * std::asin(std::min(1.0f, chord / 2.0f)));
  }
  return largest;
}

TEST_F(RetargetTest, TimeSamplingInterpolatesBetweenFramesAndClamps) {
  const Retargeter retargeter(motion_, model_);
  const double dt = motion_.frame_time;
  const int f = 1000;
  const deform::Pose a = retargeter.pose_at_frame(f), b = retargeter.pose_at_frame(f + 1);
  // At a frame's own time the sample is that frame (float rounding of t / dt only).
  EXPECT_LT(largest_rotation_difference(retargeter.pose_at_time(f * dt), a), 1e-5f);
  const deform::Pose mid = retargeter.pose_at_time((f + 0.5) * dt);
  // Halfway, the root is halfway (lerp; round-off), and each joint has turned no further from
  // either frame than the frames are from each other (slerp stays on the arc; 1e-4 rad slack).
  EXPECT_LT(glm::distance(mid.root_translation, 0.5f * (a.root_translation + b.root_translation)),
            1e-5f);
  const float step = largest_rotation_difference(a, b);
  EXPECT_GT(step, 1e-3f);  // the two frames differ, so the check below means something
  EXPECT_LE(largest_rotation_difference(mid, a), step + 1e-4f);
  EXPECT_LE(largest_rotation_difference(mid, b), step + 1e-4f);
  // Clamped to the clip: the end frames, up to slerp's round-off at a weight of 0.
  EXPECT_LT(largest_rotation_difference(retargeter.pose_at_time(-5.0), retargeter.pose_at_frame(0)),
            1e-5f);
  EXPECT_LT(largest_rotation_difference(retargeter.pose_at_time(1e6),
                                        retargeter.pose_at_frame(motion_.frame_count - 1)),
            1e-5f);
  EXPECT_THROW(retargeter.pose_at_frame(-1), std::out_of_range);
  EXPECT_THROW(retargeter.pose_at_frame(motion_.frame_count), std::out_of_range);
}

TEST_F(RetargetTest, PrefixedClipNamesMatchByRoleAndHierarchy) {
  Clip prefixed = motion_;
  for (ClipJoint& joint : prefixed.joints) joint.name = "mocap:" + joint.name;
  const Retargeter retargeter(prefixed, model_);
  for (const char* name : {"Hips", "LowerBack", "Spine", "Spine1", "Neck", "Neck1", "Head",
                           "LeftArm", "LeftForeArm", "LeftHand", "RightUpLeg", "RightFoot"}) {
    const int m = model_joint(name);
    ASSERT_GE(retargeter.bvh_joint_for(m), 0) << name << " unmapped";
    EXPECT_EQ(prefixed.joints[retargeter.bvh_joint_for(m)].name, std::string("mocap:") + name);
  }
  // The same poses as with the plain names, bit for bit: the same joints are paired.
  const Retargeter plain(motion_, model_);
  const deform::Pose p = retargeter.pose_at_frame(500), q = plain.pose_at_frame(500);
  for (const auto& [joint, child] : kLimbBones) {
    const int m = model_joint(joint);
    EXPECT_EQ(p.local_rotations[m], q.local_rotations[m]) << joint;
  }
}

TEST_F(RetargetTest, NameMapPairsOrLeavesOutJoints) {
  const JointNameMap map{.source = "",
                         .pairs = {{"Head", std::nullopt}, {"LFingers", "LeftHandFinger1"}}};
  const Retargeter retargeter(motion_, model_, map);
  const int left = retargeter.bvh_joint_for(model_joint("LeftHandFinger1"));
  ASSERT_GE(left, 0);
  EXPECT_EQ(motion_.joints[left].name, "LFingers");
  const auto found = std::find_if(retargeter.matches().begin(), retargeter.matches().end(),
                                  [&](const JointMatch& m) { return m.bvh_joint == left; });
  ASSERT_NE(found, retargeter.matches().end());
  EXPECT_EQ(found->reason, JointMatchReason::kNameMap);
  // Left out: Head (by the map) and the fingers and thumbs the map does not pair.
  EXPECT_EQ(retargeter.unmapped_bvh_joints(),
            (std::vector<std::string>{"Head", "LeftFingerBase", "LThumb", "RightFingerBase",
                                      "RFingers", "RThumb"}));
  EXPECT_EQ(retargeter.unmapped_model_joints(),
            (std::vector<std::string>{"Head", "LThumb", "LeftFingerBase", "RThumb",
                                      "RightFingerBase", "RightHandFinger1"}));
}

TEST_F(RetargetTest, NameMapDrivesAThumb) {
  const JointNameMap map{.source = "", .pairs = {{"LThumb", "LThumb"}}};
  const Retargeter retargeter(motion_, model_, map);
  const int m = model_joint("LThumb");
  ASSERT_GE(retargeter.bvh_joint_for(m), 0);
  EXPECT_EQ(motion_.joints[retargeter.bvh_joint_for(m)].name, "LThumb");
  EXPECT_EQ(retargeter.unmapped_bvh_joints(),
            (std::vector<std::string>{"LeftFingerBase", "LFingers", "RightFingerBase", "RFingers",
                                      "RThumb"}));
  // Driven: the clip turns the thumb against the hand in this frame.
  const deform::Pose pose = retargeter.pose_at_frame(1300);
  EXPECT_NE(pose.local_rotations[m], model_.skeleton.joints[m].rest_rotation);
}

TEST_F(RetargetTest, NameMapDrivesAToe) {
  const JointNameMap map{.source = "", .pairs = {{"LeftToeBase", "LeftToeBase"}}};
  const Retargeter retargeter(motion_, model_, map);
  expect_toes_paired_but_undriven(retargeter, model_.skeleton, {"LeftToeBase"});
}

TEST_F(RetargetTest, BadNameMapsNameTheMapAndTheJoint) {
  const std::pair<JointNamePair, const char*> cases[] = {
      {{"Nope", "Hips"}, "Nope"},
      {{"Hips", "Pelvis"}, "Pelvis"},
  };
  for (const auto& [pair, expected] : cases) {
    try {
      Retargeter(motion_, model_, JointNameMap{.source = "bad_map.json", .pairs = {pair}});
      ADD_FAILURE() << "no error for " << pair.clip_joint;
    } catch (const std::invalid_argument& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("bad_map.json"), std::string::npos) << message;
      EXPECT_NE(message.find(expected), std::string::npos) << message;
    }
  }
}

// Nothing unmapped in silence (issue 48): a clip joint the model lacks, under a name that
// matches nothing (a misspelt "HeadTop"), drives no model joint and is named in a warning; the
// clip's joints all matched before it came, so without it no such warning is given.
TEST_F(RetargetTest, AClipJointThatMatchesNothingIsNamedInAWarning) {
  const auto clip_warning = [](const Retargeter& retargeter) {
    for (const std::string& warning : retargeter.warnings())
      if (warning.starts_with("clip joints that drive no model joint")) return warning;
    return std::string();
  };
  EXPECT_EQ(clip_warning(Retargeter(motion_, model_)), "");
  Clip misspelt = motion_;
  ClipJoint head_top;  // no channels: every frame's values stay as they are
  head_top.name = "HeadTpo";
  head_top.parent = misspelt.find("Head");
  head_top.offset = {0.0f, 0.1f, 0.0f};
  head_top.channel_offset = misspelt.channel_count;
  misspelt.joints.push_back(head_top);
  const Retargeter retargeter(misspelt, model_);
  EXPECT_EQ(retargeter.unmapped_bvh_joints().back(), "HeadTpo");
  EXPECT_EQ(clip_warning(retargeter),
            "clip joints that drive no model joint (1): HeadTpo; pair them in a joint name map "
            "to drive them");
  // Left out by a name map on purpose, it is still named: nothing it drives moves.
  const Retargeter left_out(misspelt, model_, {.source = "", .pairs = {{"HeadTpo", std::nullopt}}});
  EXPECT_NE(clip_warning(left_out).find("HeadTpo"), std::string::npos);
}

}  // namespace
}  // namespace sweepd::motion::retarget_test
