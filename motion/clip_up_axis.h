// Up axis of a channel clip (a BVH file): which of the clip's axes points up in its rest pose,
// and the turn that makes a Z-up clip Y-up, the convention motion/retarget.h expects.
//
// clip_rest_skeleton(clip)  the clip's rest pose (every channel zero) as a deform::Skeleton:
//                           joints in clip order, offsets as rest translations, rest rotations
// detect_up_axis(clip)      kZ when the clip's rest skeleton stands along ±Z more than along
//                           ±Y, else kY. "Stands along": from the mean of its feet to its head
//                           (or from its pelvis to its chest when a foot or the head is
//                           missing), joints found by deform::detect_rig_map, names then shape;
//                           kY when no rig map is found (no torso chain).
// turn_z_up_to_y_up(clip)   turns the clip by -90° about X, (x, y, z) -> (x, z, -y), in place:
//                           offsets, End Sites and rest rotations rotated; Yrotation and
//                           Yposition channels become Zrotation and Zposition with their values
//                           negated, Zrotation and Zposition become Yrotation and Yposition.
//                           Every frame's world pose is the original's turned, so the feet that
//                           stood on the XY plane stand on the XZ plane. No per-frame cost.
//                           Throws std::invalid_argument for a keyframed clip (glTF is Y-up).
// up_axis_from_name("y"|"z"), to_string(axis): the spelling of --bvh-up.
#pragma once

#include <optional>
#include <string_view>

#include "deform/model/skeleton.h"
#include "motion/clip.h"

namespace sweepd::motion {

enum class UpAxis { kY, kZ };

std::optional<UpAxis> up_axis_from_name(std::string_view name);
const char* to_string(UpAxis axis);

deform::Skeleton clip_rest_skeleton(const Clip& clip);
UpAxis detect_up_axis(const Clip& clip);
void turn_z_up_to_y_up(Clip& clip);

}  // namespace sweepd::motion
