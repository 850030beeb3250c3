// How far a retargeted model faces from the clip (issue 48 item 2), per frame: the angle about
// the vertical between the model's hips (left thigh joint minus right, the rig map's leg roles,
// posed) and the clip's (its LeftUpLeg minus RightUpLeg), both made horizontal.
//   yaw_between(a, b)                          signed degrees about +Y from a to b
//   worst_facing_difference(model, clip, r)    the largest |angle| over every frame (degrees)
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "deform/model/forward_kinematics.h"
#include "deform/rig/rig_map.h"
#include "motion/retarget.h"
#include "tests/motion/clip_world_positions.h"

namespace sweepd::test {

inline float yaw_between(glm::vec3 a, glm::vec3 b) {
  a.y = b.y = 0.0f;
  return glm::degrees(std::atan2(glm::cross(a, b).y, glm::dot(a, b)));
}

inline float worst_facing_difference(const deform::Model& model, const motion::Clip& clip,
                                     const motion::Retargeter& retargeter) {
  const deform::RigMap map = deform::detect_rig_map(model.skeleton);
  const int clip_left = clip.find("LeftUpLeg"), clip_right = clip.find("RightUpLeg");
  EXPECT_GE(clip_left, 0);
  EXPECT_GE(clip_right, 0);
  std::vector<glm::mat4> world(model.skeleton.size());
  float worst = 0.0f;
  for (int frame = 0; frame < clip.frame_count; ++frame) {
    deform::forward_kinematics(model.skeleton, retargeter.pose_at_frame(frame), world);
    const glm::vec3 model_left =
        glm::vec3(world[map.left_leg.upper][3]) - glm::vec3(world[map.right_leg.upper][3]);
    const std::vector<glm::vec3> at = motion::clip_world_positions(clip, frame);
    const glm::vec3 clip_left_vector = at[clip_left] - at[clip_right];
    worst = std::max(worst, std::abs(yaw_between(model_left, clip_left_vector)));
  }
  return worst;
}

}  // namespace sweepd::test
