// The range-of-motion clip (motion/range_of_motion.h) on every shared body — the shared male,
// the RiggedFigure, the four corpus bodies (four rig conventions, a one-joint torso among them)
// — as is, mirrored and at 0.6x: each move reaches its stated angle, in the body's own
// directions (forward, up, outward), whatever its rest pose, facing and size.
//
// Angles are measured on the posed skeleton (forward kinematics of the clip's frame): the
// angle between a bone's rest and posed world directions. Tolerance 1.5°: the swing is exact
// up to float rounding, but the direction measured (joint to joint) is not always the one
// swung (a twist or segment bone between the roles bends the line by up to a degree).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "deform/model/forward_kinematics.h"
#include "io/gltf/gltf_load.h"
#include "motion/own_skeleton_clip.h"
#include "motion/range_of_motion.h"
#include "tests/body_variants.h"

namespace sweepd::motion {
namespace {

namespace fs = std::filesystem;

constexpr double kDegreesTolerance = 1.5;

struct PosedBody {
  std::vector<glm::mat4> rest, posed;
  glm::vec3 at(int joint) const { return glm::vec3(posed[joint][3]); }
  glm::vec3 rest_at(int joint) const { return glm::vec3(rest[joint][3]); }
  glm::vec3 direction(int from, int to) const { return glm::normalize(at(to) - at(from)); }
  glm::vec3 rest_direction(int from, int to) const {
    return glm::normalize(rest_at(to) - rest_at(from));
  }
  // How squarely the bone swung towards `toward`: the cosine between the posed direction's part
  // across the rest direction and toward's part across it (1: in the plane of the two).
  float swung_towards(int from, int to, glm::vec3 toward) const {
    const glm::vec3 d = rest_direction(from, to), p = direction(from, to);
    return glm::dot(glm::normalize(p - glm::dot(p, d) * d),
                    glm::normalize(toward - glm::dot(toward, d) * d));
  }
  // Degrees between the bone's rest and posed directions.
  double turned(int from, int to) const {
    const double c = glm::clamp(glm::dot(direction(from, to), rest_direction(from, to)), -1.0f, 1.0f);
    return std::acos(c) * 180.0 / M_PI;
  }
};

class RangeOfMotionOnEveryBody : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    const fs::path data(SWEEPD_SHARED_DATA);
    const std::vector<std::string> files = {
        "models/makehuman_male_cmu.glb",
        "models/RiggedFigure/RiggedFigure.gltf",
        "models/corpus/makehuman_child_mixamo_unity.glb",
        "models/corpus/makehuman_female_old_heavy_mixamo.glb",
        "models/corpus/makehuman_female_slim_openpose.glb",
        "models/corpus/makehuman_male_old_heavy_unreal.glb"};
    std::vector<deform::Model> models;
    for (const std::string& file : files)
      if (fs::exists(data / file)) models.push_back(io::load_gltf(data / file));
    std::vector<std::pair<std::string, const deform::Model*>> named;
    for (std::size_t i = 0; i < models.size(); ++i) named.push_back({files[i], &models[i]});
    variants_ = new std::vector<test_models::BodyVariant>(
        test_models::plain_mirrored_and_rescaled(named, 0.6f));
  }
  static void TearDownTestSuite() { delete variants_; }
  void SetUp() override {
    if (variants_->size() < 18) GTEST_SKIP() << "shared data absent (see ../shared/data/SOURCES.md)";
  }

  static std::vector<test_models::BodyVariant>* variants_;
};
std::vector<test_models::BodyVariant>* RangeOfMotionOnEveryBody::variants_ = nullptr;

glm::quat rotation_of(const glm::mat4& m) {
  return glm::normalize(glm::quat_cast(
      glm::mat3(glm::normalize(glm::vec3(m[0])), glm::normalize(glm::vec3(m[1])),
                glm::normalize(glm::vec3(m[2])))));
}

// A body's rig map, rest axes and range of motion.
struct BodyRom {
  explicit BodyRom(const deform::Model& model)
      : map(deform::detect_rig_map(model.skeleton)),
        axes(deform::rest_body_axes(map, model.skeleton.world_rest_matrices())),
        rom(range_of_motion(model.skeleton, map)) {}
  deform::RigMap map;
  deform::BodyAxes axes;
  RangeOfMotion rom;
};

// The body posed at the peak of the move named `move` (which must exist).
PosedBody at_peak(const deform::Model& model, const RangeOfMotion& rom, const std::string& move) {
  const OwnSkeletonClip player(rom.clip, model.skeleton);
  PosedBody body;
  body.rest = model.skeleton.world_rest_matrices();
  body.posed.resize(body.rest.size());
  for (const RomMove& m : rom.moves)
    if (m.name == move) {
      deform::forward_kinematics(model.skeleton, player.pose_at_frame(m.peak_frame), body.posed);
      return body;
    }
  ADD_FAILURE() << "no move '" << move << "'";
  return body;
}

TEST_F(RangeOfMotionOnEveryBody, EveryFrameIsAValidPoseThatStartsAndEndsAtRest) {
  for (const test_models::BodyVariant& body : *variants_) {
    SCOPED_TRACE(body.name);
    const BodyRom b(body.model);
    const auto& [map, axes, rom] = b;
    // 48 moves; the OpenPose body has no spine to bend (one joint) and no hand joints: 38.
    EXPECT_GE(rom.moves.size(), 38u);
    EXPECT_EQ(rom.clip.frame_count,
              static_cast<int>(rom.moves.size()) * kRomFramesPerMove + 1);
    const OwnSkeletonClip player(rom.clip, body.model.skeleton);
    const deform::Pose rest = deform::rest_pose(body.model.skeleton);
    for (int frame = 0; frame < rom.clip.frame_count; frame += 7) {
      deform::Pose pose = player.pose_at_frame(frame);
      ASSERT_EQ(deform::normalize_and_validate(pose, body.model.skeleton, 1e-4), "")
          << "frame " << frame;
    }
    for (const int frame : {0, rom.clip.frame_count - 1}) {
      const deform::Pose pose = player.pose_at_frame(frame);
      for (std::size_t j = 0; j < rest.local_rotations.size(); ++j)
        EXPECT_GT(std::abs(glm::dot(pose.local_rotations[j], rest.local_rotations[j])),
                  1.0f - 1e-6f)
            << "frame " << frame << " joint " << body.model.skeleton.joints[j].name;
    }
  }
}

TEST_F(RangeOfMotionOnEveryBody, LegsReachTheirAnglesInTheBodysOwnDirections) {
  for (const test_models::BodyVariant& body : *variants_) {
    SCOPED_TRACE(body.name);
    const BodyRom b(body.model);
    const auto& [map, axes, rom] = b;
    const PosedBody flexed = at_peak(body.model, rom, "hip flexion 130°");
    const PosedBody abducted = at_peak(body.model, rom, "hip abduction 45°");
    const PosedBody knees = at_peak(body.model, rom, "knee flexion 150°");
    for (const auto& [leg, side] : {std::pair{&map.left_leg, 1.0f}, {&map.right_leg, -1.0f}}) {
      EXPECT_NEAR(flexed.turned(leg->upper, leg->lower), 130.0, kDegreesTolerance);
      EXPECT_GT(glm::dot(flexed.direction(leg->upper, leg->lower), axes.forward), 0.5f)
          << "the thigh comes up in front";
      EXPECT_NEAR(abducted.turned(leg->upper, leg->lower), 45.0, kDegreesTolerance);
      EXPECT_GT(glm::dot(abducted.direction(leg->upper, leg->lower), side * axes.left), 0.5f)
          << "the thigh goes outwards";
      EXPECT_NEAR(knees.turned(leg->lower, leg->foot), 150.0, kDegreesTolerance);
      EXPECT_GT(knees.swung_towards(leg->lower, leg->foot, -axes.forward), 0.99f)
          << "the shin folds back";
      EXPECT_NEAR(knees.turned(leg->upper, leg->lower), 0.0, kDegreesTolerance)
          << "the thigh stays";
    }
  }
}

TEST_F(RangeOfMotionOnEveryBody, ArmsReachTheirDirectionsAndElbowsBend) {
  for (const test_models::BodyVariant& body : *variants_) {
    SCOPED_TRACE(body.name);
    const BodyRom b(body.model);
    const auto& [map, axes, rom] = b;
    const PosedBody overhead = at_peak(body.model, rom, "arms overhead");
    const PosedBody forward = at_peak(body.model, rom, "arms forward");
    const PosedBody elbows = at_peak(body.model, rom, "elbow flexion 150°");
    for (const deform::ArmJoints* arm : {&map.left_arm, &map.right_arm}) {
      // The upper arm's target direction is reached exactly (a shortest arc onto it).
      EXPECT_GT(glm::dot(overhead.direction(arm->upper, arm->lower), axes.up), 0.96f);
      EXPECT_GT(glm::dot(forward.direction(arm->upper, arm->lower), axes.forward), 0.999f);
      if (arm->hand < 0) continue;  // OpenPose: the forearm's end is not a joint
      EXPECT_NEAR(elbows.turned(arm->lower, arm->hand), 150.0, kDegreesTolerance);
      EXPECT_GT(elbows.swung_towards(arm->lower, arm->hand, axes.forward), 0.99f)
          << "the forearm comes forward";
    }
  }
}

TEST_F(RangeOfMotionOnEveryBody, TheSpineBendsByItsWholeAngleOverItsJoints) {
  for (const test_models::BodyVariant& body : *variants_) {
    SCOPED_TRACE(body.name);
    const BodyRom b(body.model);
    const auto& [map, axes, rom] = b;
    if (map.torso.chain.size() < 2) {  // a one-joint torso: nothing above the pelvis bends
      for (const RomMove& move : rom.moves) EXPECT_EQ(move.name.find("spine"), std::string::npos);
      continue;
    }
    const PosedBody bent = at_peak(body.model, rom, "spine flexion 70°");
    const int chest = map.torso.chest();
    const glm::quat turn = rotation_of(bent.posed[chest]) * glm::inverse(rotation_of(bent.rest[chest]));
    const double degrees = 2.0 * std::acos(std::min(1.0f, std::abs(glm::normalize(turn).w))) *
                           180.0 / M_PI;
    EXPECT_NEAR(degrees, 70.0, kDegreesTolerance) << "the chest turns by the whole bend";
  }
}

}  // namespace
}  // namespace sweepd::motion
