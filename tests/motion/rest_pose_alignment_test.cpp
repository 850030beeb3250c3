// Rest-pose alignment (motion/retarget.h): what differs for a reason is corrected, what is
// anatomy is kept.
// - Onto a copy of the clip's own skeleton every driven joint gets the clip's own local rotation
//   (within 1e-5 per quaternion component: float round-off through chains of up to 8 joints).
// - Onto a skeleton that differs from the clip's only by rest angles of the spine (12°) and the
//   neck (25° forward, the head upright), the head's world pitch stays within 2° of the clip's on
//   every frame of both shared clips (aligning the neck's bone like a limb's tilted it by the
//   neck's lean).
// - On the shared male, RiggedFigure and the mannequin, every frame of both clips, the head turns
//   from its rest exactly as the clip's head turns from its rest (within 0.01°), whatever the
//   neck's lean at rest (printed: the angle between each model's rest neck and the clip's).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "io/bvh/bvh_load.h"
#include "io/gltf/gltf_load.h"
#include "mannequin/mannequin.h"
#include "motion/retarget.h"

namespace sweepd::motion::rest_pose_alignment_test {
namespace {

namespace fs = std::filesystem;

const fs::path kData = SWEEPD_SHARED_DATA;
constexpr float kCmuUnit = 0.056444f;  // metres per CMU BVH unit
const char* const kClips[] = {"cmu_01_01.bvh", "cmu_01_03.bvh"};

bool have_data() {
  for (const char* clip : kClips)
    if (!fs::exists(kData / "motion" / clip)) return false;
  return fs::exists(kData / "models/makehuman_male_cmu.glb") &&
         fs::exists(kData / "models/RiggedFigure/RiggedFigure.gltf");
}

Clip load_clip(const char* name) {
  return io::load_bvh(kData / "motion" / name, {.length_scale = kCmuUnit});
}

// The clip's skeleton as a model's: same names, parents and offsets, identity rests.
deform::Skeleton copy_of(const Clip& clip) {
  deform::Skeleton skeleton;
  for (const ClipJoint& joint : clip.joints)
    skeleton.joints.push_back(
        {.name = joint.name, .parent = joint.parent, .rest_translation = joint.offset});
  return skeleton;
}

// World rotations from local ones (parents first).
std::vector<glm::quat> world_rotations(const std::vector<int>& parents,
                                       const std::vector<glm::quat>& local) {
  std::vector<glm::quat> world(local.size());
  for (std::size_t j = 0; j < local.size(); ++j)
    world[j] = parents[j] < 0 ? local[j] : world[parents[j]] * local[j];
  return world;
}

std::vector<int> parents_of(const deform::Skeleton& skeleton) {
  std::vector<int> parents;
  for (const deform::Joint& joint : skeleton.joints) parents.push_back(joint.parent);
  return parents;
}

std::vector<glm::quat> clip_world(const Clip& clip, int frame) {
  std::vector<glm::quat> local(clip.joints.size());
  std::vector<glm::vec3> translations(clip.joints.size());
  clip.local_pose(frame, local, translations);
  std::vector<int> parents;
  for (const ClipJoint& joint : clip.joints) parents.push_back(joint.parent);
  return world_rotations(parents, local);
}

double pitch_degrees(const glm::quat& world) {
  const glm::vec3 forward = world * glm::vec3(0, 0, 1);
  return glm::degrees(std::atan2(double{forward.y}, std::hypot(forward.x, forward.z)));
}

// The angle of the turn from a to b, in double (a float dot product alone rounds to 0.056°).
double angle_degrees(const glm::quat& a, const glm::quat& b) {
  const glm::dquat d = glm::conjugate(glm::dquat(a)) * glm::dquat(b);
  return glm::degrees(2.0 * std::atan2(glm::length(glm::dvec3(d.x, d.y, d.z)), std::abs(d.w)));
}

TEST(RestPoseAlignment, OntoACopyOfTheClipsSkeletonTheClipsRotationsComeBack) {
  if (!have_data()) GTEST_SKIP() << "shared data absent (see ../shared/data/SOURCES.md)";
  for (const char* name : kClips) {
    const Clip clip = load_clip(name);
    const Retargeter retargeter(clip, copy_of(clip));
    std::vector<glm::quat> local(clip.joints.size());
    std::vector<glm::vec3> translations(clip.joints.size());
    double worst = 0.0;
    for (int frame = 0; frame < clip.frame_count; ++frame) {
      const deform::Pose pose = retargeter.pose_at_frame(frame);
      clip.local_pose(frame, local, translations);
      for (const JointMatch& match : retargeter.matches()) {
        if (!match.driven) continue;  // toes: not measured, kept at rest (see retarget.h)
        ASSERT_EQ(match.bvh_joint, match.model_joint);
        const glm::quat a = pose.local_rotations[match.model_joint], b = local[match.bvh_joint];
        const float sign = glm::dot(a, b) < 0.0f ? -1.0f : 1.0f;
        for (int i = 0; i < 4; ++i) worst = std::max(worst, double{std::abs(a[i] - sign * b[i])});
      }
    }
    std::printf("%s onto a copy of its skeleton: largest rotation component difference %.2e\n",
                name, worst);
    EXPECT_LT(worst, 1e-5) << name;
  }
}

TEST(RestPoseAlignment, ASpineAndNeckThatLeanAtRestKeepTheHeadsPitch) {
  if (!have_data()) GTEST_SKIP() << "shared data absent (see ../shared/data/SOURCES.md)";
  for (const char* name : kClips) {
    const Clip clip = load_clip(name);
    deform::Skeleton leaning = copy_of(clip);
    const auto turn = [&](const char* joint, float degrees) {
      const int j = leaning.find(joint);
      ASSERT_GE(j, 0) << joint;
      leaning.joints[j].rest_rotation = glm::angleAxis(glm::radians(degrees), glm::vec3(1, 0, 0));
    };
    turn("LowerBack", 12.0f);  // the lower spine leans; the chest turns back upright
    turn("Spine1", -12.0f);
    turn("Neck", 25.0f);  // the neck leans forward; the head sits upright on it
    turn("Head", -25.0f);
    const Retargeter retargeter(clip, leaning);
    const int model_head = leaning.find("Head"), clip_head = clip.find("Head");
    const std::vector<int> parents = parents_of(leaning);
    double worst = 0.0;
    for (int frame = 0; frame < clip.frame_count; ++frame) {
      const deform::Pose pose = retargeter.pose_at_frame(frame);
      const glm::quat model = world_rotations(parents, pose.local_rotations)[model_head];
      const glm::quat source = clip_world(clip, frame)[clip_head];
      worst = std::max(worst, std::abs(pitch_degrees(model) - pitch_degrees(source)));
    }
    std::printf("%s onto a leaning spine and neck: largest head pitch difference %.4f degrees\n",
                name, worst);
    EXPECT_LT(worst, 2.0) << name;
  }
}

TEST(RestPoseAlignment, OnEveryModelTheHeadTurnsAsTheClipsHead) {
  if (!have_data()) GTEST_SKIP() << "shared data absent (see ../shared/data/SOURCES.md)";
  const std::pair<const char*, deform::Model> models[] = {
      {"male", io::load_gltf(kData / "models/makehuman_male_cmu.glb")},
      {"RiggedFigure", io::load_gltf(kData / "models/RiggedFigure/RiggedFigure.gltf")},
      {"mannequin", mannequin::make_mannequin({.target_vertices = 2000})}};
  for (const auto& [model_name, model] : models)
    for (const char* name : kClips) {
      const Clip clip = load_clip(name);
      const Retargeter retargeter(clip, model);
      const deform::RigMap rig = deform::detect_rig_map(model.skeleton);
      const int head = rig.neck.head;
      const int clip_head = retargeter.bvh_joint_for(head);
      ASSERT_GE(clip_head, 0) << model_name << ": its head is not matched";
      const std::vector<int> parents = parents_of(model.skeleton);
      const glm::quat rest =
          world_rotations(parents, deform::rest_pose(model.skeleton).local_rotations)[head];
      // What aligning the neck like a limb turned the head by: the rest neck's angle to the
      // clip's (model neck base to head, clip likewise).
      const std::vector<glm::mat4> world_rest = model.skeleton.world_rest_matrices();
      // A model neck joint the clip has no match for (-1) is measured from the clip head's
      // parent instead.
      const int neck = rig.neck.chain.front();
      const int clip_neck = retargeter.bvh_joint_for(neck) >= 0 ? retargeter.bvh_joint_for(neck)
                                                                : clip.joints[clip_head].parent;
      ASSERT_GE(clip_neck, 0) << model_name << ", " << name;
      std::vector<glm::vec3> clip_rest(clip.joints.size());
      for (std::size_t b = 0; b < clip.joints.size(); ++b)
        clip_rest[b] =
            (clip.joints[b].parent < 0 ? glm::vec3(0) : clip_rest[clip.joints[b].parent]) +
            clip.joints[b].offset;
      const glm::vec3 model_neck = glm::vec3(world_rest[head][3] - world_rest[neck][3]);
      const glm::vec3 source_neck = clip_rest[clip_head] - clip_rest[clip_neck];
      const double lean = glm::degrees(std::acos(std::clamp(
          double{glm::dot(glm::normalize(model_neck), glm::normalize(source_neck))}, -1.0, 1.0)));
      double worst = 0.0;
      for (int frame = 0; frame < clip.frame_count; ++frame) {
        const deform::Pose pose = retargeter.pose_at_frame(frame);
        const glm::quat turned =
            world_rotations(parents, pose.local_rotations)[head] * glm::inverse(rest);
        worst = std::max(worst, angle_degrees(turned, clip_world(clip, frame)[clip_head]));
      }
      std::printf(
          "%s, %s: rest neck %.1f degrees from the clip's; head turn differs from the clip's by "
          "at most %.4f degrees\n",
          model_name, name, lean, worst);
      EXPECT_LT(worst, 0.01) << model_name << ", " << name;
    }
}

}  // namespace
}  // namespace sweepd::motion::rest_pose_alignment_test
