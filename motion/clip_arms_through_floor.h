// The clip's arms through its floor beside a lying torso: on which clip frames the clip lays
// its torso on its floor (lying on the back or face down, sitting on the floor) and pushes an
// arm through that floor, so that the model's arm does not hold the model's body up there
// (motion/body_floor.h swings it up instead). Retargeted by rotations, a clip's limbs keep
// moving as the clip's do: cmu_01_01 knocked down forwards swings its walking arms 11-22 cm
// below the clip's floor while its chest lies on it, and lifting the whole model by that hand
// left the model's chest 14-24 cm above the floor.
//
// A clip's torso lies on a frame where its lowest torso joint (pelvis, spine, chest, neck,
// head) stands no higher above the clip's floor than kLyingTorsoHeight of its hip height (a
// lying body's joints are about its half thickness up: CMU knocked down, 0.14-0.19 of the hip
// height at the pelvis, -0.02-0.16 at the chest; a kneeling or crouching pelvis stays above
// 0.3 of it). An arm goes through the floor where any of its joints (its upper joint and
// every joint below it: elbow, wrist, fingers) lies below the clip's floor: no arm of a real
// body does, so the clip's own pose says that the arm, not the torso, is wrong there.
// Inputs:  the clip, its torso joints (-1 ignored), each arm's upper joint (the model's left,
//          right; clip joints, -1: none), the clip's floor (y), its hip height (the root
//          scale's).
// Output:  per clip frame, a bit per arm (1 the left, 2 the right) set where the torso lies and
//          that arm goes through the floor.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "motion/clip.h"

namespace sweepd::motion {

inline constexpr float kLyingTorsoHeight = 0.2f;

std::vector<std::uint8_t> clip_arms_through_floor(const Clip& clip, std::span<const int> torso,
                                                  std::array<int, 2> arms, float floor,
                                                  float hip_height);

}  // namespace sweepd::motion
