// range_of_motion: a clip that takes any rig through the human body's range of motion, made from
// its rig map (issue 47) — what `sweepctl rom` writes, what `sweepctl check` measures by default,
// so that a body is judged on the poses that break deformers, not only on the clips at hand.
//
// Each move goes from rest to its peak and back: every limb joint through its anatomical range
// alone (both sides mirrored at once), then combined poses (knee to chest, deep squat, kneeling,
// a lunge, reaching overhead with a side bend, a twist with the arms across the chest):
//   legs   hip flexion 130°, extension 30°, abduction 45°, adduction 20°, rotation ±40°;
//          knee 150°; ankle dorsiflexion 20°, plantar flexion 45°
//   spine  flexion 70°, extension 30°, side bend ±35°, twist ±45° (spread over the joints
//          above the pelvis; a one-joint torso has none and skips them)
//   neck   flexion 45°, extension 45°, side bend ±40°, twist ±70° (spread over the neck chain)
//   arms   the upper arm to fixed directions of the body: down, out to the side, overhead
//          (abduction ~165°), forward, forward and up (flexion ~170°), across the chest,
//          back at shoulder height, behind the back; clavicle shrug 25°, forward 20°, back 15°;
//          elbow 150°; forearm twist ±80°; wrist ±60° and ±30°
// Directions come from the body's rest axes (deform::rest_body_axes: up, left, forward) and
// the rest bones, so the clip fits a T-pose, an A-pose, any up axis and any facing. A joint's
// turn R is given in the rest world frame and applied in the joint's own frame
// (local = rest_local * W⁻¹ R W, W its rest world rotation), so a child turns relative to its
// posed parent as anatomy does. Roles absent from the map (no clavicle, no hand, no neck) skip
// their moves.
//
// Output: a keyframed motion::Clip on the model's own skeleton (joints named and ordered as the
// skeleton's, rest offsets and rotations its own; play it with motion::OwnSkeletonClip), linear
// rotation tracks for the joints it moves, 1 s per move at kRomFramesPerSecond with the peak at
// its middle frame; and the moves, named, with their frames.
#pragma once

#include <string>
#include <vector>

#include "deform/model/skeleton.h"
#include "deform/rig/rig_map.h"
#include "motion/clip.h"

namespace sweepd::motion {

// The animation name `sweepctl rom` writes.
inline constexpr const char* kRomClipName = "range of motion";
inline constexpr int kRomFramesPerSecond = 30;
inline constexpr int kRomFramesPerMove = 30;  // rest at its first frame, the peak at its 15th

struct RomMove {
  std::string name;  // "hip flexion 130°", "deep squat", ...
  int first_frame = 0;
  int peak_frame = 0;
};

struct RangeOfMotion {
  Clip clip;
  std::vector<RomMove> moves;
  // The move a clip frame belongs to ("rest" past the last move).
  const std::string& move_at(int frame) const;
};

// Requires a map that fits the skeleton (deform::validate_rig_map).
RangeOfMotion range_of_motion(const deform::Skeleton& skeleton, const deform::RigMap& map);

}  // namespace sweepd::motion
