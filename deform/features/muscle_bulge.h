// Muscle bulge (paper §4.3): the biceps swells as the elbow bends (the calves, optionally, as
// the knee bends).
//
// The upper-arm link keys of each arm sweep (the shin's link keys for the calves, on the back)
// grow on the muscle's side only: the key's half-axis nearest the `front` direction (taken at rest,
// in the key's own frame, so it turns with the limb) grows by δ = gain · h · s(φ) · profile(u), and
// the centre moves by δ towards the front, so the back of the section stays where it was and the
// front moves out by 2δ. s(φ) = smoothstep(φ / full_flexion) of the joint's turn φ (0 at rest,
// 1 from full_flexion on, monotone); profile(u) = sin(π u) over the link (u: the key's fraction
// along it), largest in the middle of the muscle.
// Inputs:  a sweep's anchors and rest keys, the rig, the joint rotation deltas (J).
// Output:  keys (the posed keys of that sweep) changed in place; other sweeps are untouched.
// No allocation.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <span>

#include "deform/binding/bound_model.h"

namespace sweepd::deform {

struct MuscleBulgeOptions {
  bool biceps = true;
  bool calves = false;
  float biceps_gain = 0.12f;  // front half-axis growth at full flexion, relative (0.12: +12 %)
  float calf_gain = 0.06f;
  float full_flexion_degrees = 150.0f;
  glm::vec3 front{0.0f, 0.0f, 1.0f};  // the model's front at rest (glTF models face +Z)
};

// s(φ): 0 at φ = 0, 1 from full_flexion on, C1 and monotone.
float bulge_activation(float turn_radians, const MuscleBulgeOptions& options);

void apply_muscle_bulge(const BoundModel& bound, int sweep,
                        std::span<const glm::quat> joint_rotation,
                        const MuscleBulgeOptions& options, std::span<KeyEllipse> keys);

}  // namespace sweepd::deform
