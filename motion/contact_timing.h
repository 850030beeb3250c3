#pragma once
// What foot planting (foot_planting.cpp) and the other resting parts (body_contacts.cpp) share
// about a contact: how fast a part may move and still rest, over which window its speed is
// measured, and how fast a hold fades; and which joints a chain's skin moves with.

#include "deform/model/skeleton.h"

namespace sweepd::motion {

// A part rests while it moves slower than this fraction of the hip height per second (0.36 m/s
// for a 0.9 m hip).
inline constexpr float kContactSpeed = 0.4f;
// s: a contact's speed is measured this far each side of its frame.
inline constexpr double kSpeedWindow = 0.05;
// s: a hold or an offset fades to zero over this at least.
inline constexpr double kFade = 0.15;

// Whether `joint` is `ancestor` or lies below it in the skeleton.
inline bool is_at_or_below(const deform::Skeleton& skeleton, int joint, int ancestor) {
  for (int j = joint; j >= 0; j = skeleton.joints[j].parent)
    if (j == ancestor) return true;
  return false;
}

}  // namespace sweepd::motion
