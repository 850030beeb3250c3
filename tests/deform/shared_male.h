// Test fixture: the shared male (makehuman_male_cmu.glb) bound once per test program, and poses
// that turn one joint about a world axis (its rest frames are world-aligned, so a local rotation
// is a world rotation at that joint).
#pragma once

#include <filesystem>
#include <glm/gtc/quaternion.hpp>
#include <span>
#include <string>
#include <vector>

#include "deform/binding/bind.h"
#include "deform/job/deform_job.h"
#include "deform/model/joint_flexion.h"
#include "deform/model/pose.h"
#include "deform/rig/rig_map.h"
#include "io/gltf/gltf_load.h"
#include "tests/test_paths.h"

namespace sweepd::deform::test {

// The bound male, or nullptr when the shared data is absent.
inline const BoundModel* shared_male() {
  static const BoundModel* bound = []() -> const BoundModel* {
    const std::filesystem::path file =
        std::filesystem::path(SWEEPD_SHARED_DATA) / "models/makehuman_male_cmu.glb";
    if (!std::filesystem::exists(file)) return nullptr;
    const Model model = io::load_gltf(file);
    return new BoundModel(bind(model, detect_rig_map(model.skeleton)));
  }();
  return bound;
}

#define REQUIRE_SHARED_MALE()                                     \
  if (!::sweepd::deform::test::shared_male())                     \
    GTEST_SKIP() << "shared data absent: makehuman_male_cmu.glb"; \
  const ::sweepd::deform::BoundModel& male = *::sweepd::deform::test::shared_male()

inline glm::vec3 rest_joint_position(const Model& model, const std::string& name) {
  return glm::vec3(model.skeleton.world_rest_matrices()[model.skeleton.find(name)][3]);
}

// Adds a turn of `degrees` about a world axis at `joint` to the pose.
inline void turn(const Model& model, Pose& pose, const std::string& joint, glm::vec3 axis,
                 float degrees) {
  pose.local_rotations[model.skeleton.find(joint)] =
      glm::angleAxis(glm::radians(degrees), glm::normalize(axis));
}

// The left elbow's flexion axis: orthogonal to the upper arm and the model's front (+Z).
inline glm::vec3 left_elbow_flexion_axis(const Model& model) {
  const glm::vec3 upper =
      rest_joint_position(model, "LeftForeArm") - rest_joint_position(model, "LeftArm");
  return glm::normalize(glm::cross(glm::normalize(upper), glm::vec3(0, 0, 1)));
}

// The left elbow and left knee flexed to `degrees`: the angle between each joint's links, not
// a turn from rest (the male's rest pose already flexes the elbow 46°;
// deform/model/joint_flexion.h).
inline Pose left_elbow_and_knee_flexed(const Model& model, float degrees) {
  Pose pose = rest_pose(model.skeleton);
  flex_joint(model.skeleton, pose, model.skeleton.find("LeftForeArm"),
             left_elbow_flexion_axis(model), degrees);
  flex_joint(model.skeleton, pose, model.skeleton.find("LeftLeg"), glm::vec3(1, 0, 0), degrees);
  return pose;
}

inline Pose left_elbow_bent(const Model& model, float degrees) {
  Pose pose = rest_pose(model.skeleton);
  turn(model, pose, "LeftForeArm", left_elbow_flexion_axis(model), degrees);
  return pose;
}

inline int sweep_of(const BoundModel& bound, BodyPart part) {
  for (std::size_t s = 0; s < bound.sweeps.size(); ++s)
    if (bound.sweeps[s].part == part) return static_cast<int>(s);
  return -1;
}

// The spine bent forward at the torso's second joint (the male's LowerBack): turned `degrees`
// about the body's left axis, which takes its up towards its front.
inline Pose spine_bent_forward(const BoundModel& bound, float degrees) {
  const Skeleton& skeleton = bound.model.skeleton;
  const BodyAxes axes = rest_body_axes(bound.rig, skeleton.world_rest_matrices());
  Pose pose = rest_pose(skeleton);
  turn_joint(skeleton, pose, bound.rig.torso.chain.at(1), glm::cross(axes.up, axes.forward),
             degrees);
  return pose;
}

// What a test deforms with: one model's runtime and one context (deform/job/), the features and
// options of the jobs it runs, and the last job's report.
struct Posing {
  explicit Posing(const BoundModel& bound) : runtime(bound) { context.prepare(runtime); }
  ModelRuntime runtime;
  DeformContext context;
  AnatomicalFeatures features;
  DeformJobOptions options;
  DeformReport report;

  void deform(Pose& pose, DeformMethod method, std::span<glm::vec3> positions,
              std::span<glm::vec3> normals = {}, int threads = 1) {
    DeformJob job{runtime, pose, method, features, options, positions, normals};
    job.options.threads = threads;
    report = job.run(context);
  }
  SweepPoser& sweep_poser() { return context.sweep_poser(); }
  const BoundModel& bound() const { return runtime.bound(); }
  std::span<const glm::mat4> skinning() const { return context.skinning(); }
  std::span<const glm::mat4> world_pose() const { return context.world_pose(); }
};

inline std::vector<glm::vec3> deformed(Posing& posing, Pose pose, DeformMethod method) {
  std::vector<glm::vec3> positions(posing.runtime.bound().model.vertex_count());
  posing.deform(pose, method, positions);
  return positions;
}

}  // namespace sweepd::deform::test
