// The clip's resting knees: on which clip frames the clip puts each knee on its floor (kneeling,
// lying with the legs stretched), so that the model's knee is brought down onto the model's
// floor there (motion/retarget.h) whatever the model's proportions: retargeted by rotations, a
// body whose thighs are shorter than the clip's, relative to its shins, kneels with its knee
// held above the floor by its other, planted foot (the heavy male: 8 cm up).
//
// A clip's knee rests on a frame where its joint stands no higher above the clip's floor than
// the clip's standing ankle joint (Retargeter's stance: a knee is about as thick as an ankle
// stands high) plus a resting part's contact height (motion/body_contacts.h: 0.035 of the hip
// height, 3 cm on CMU's 0.94 m). A walking clip's knees never come within 30 cm of that.
// Inputs:  the clip, its knee joints (the clip joints driving the model's left and right knees;
//          -1: none), the clip's floor (y), its standing ankle's height above that floor and its
//          hip height (the root scale's).
// Output:  per side (the model's left, right), per clip frame, 1 where that knee rests; empty
//          for a side without a knee.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "motion/clip.h"

namespace sweepd::motion {

std::array<std::vector<std::uint8_t>, 2> clip_resting_knees(const Clip& clip,
                                                            std::array<int, 2> knees, float floor,
                                                            float ankle_height, float hip_height);

}  // namespace sweepd::motion
