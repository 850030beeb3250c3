// The floor figures of issue 48's targets, on a retargeted clip:
//   lowest(positions)                     the lowest y of a point set (m)
//   lowest_over_clip(bound, poses)        how far the swept body goes below its floor (the rest
//                                         mesh's lowest vertex) over every 10th frame of a
//                                         player's poses (m, negative below)
//   lowest_over_clip(bound, clip, feet)   the same, the clip retargeted with those feet
//   worst_foot_slide(r)                   the worst slide of a planted foot over one contact (m),
//                                         on the retargeter's own poses (it must plant feet)
#pragma once

#include <algorithm>
#include <limits>
#include <span>
#include <vector>

#include "deform/binding/bind.h"
#include "motion/retarget.h"
#include "tests/deform/shared_male.h"

namespace sweepd::test {

inline float lowest(std::span<const glm::vec3> positions) {
  float y = std::numeric_limits<float>::infinity();
  for (const glm::vec3& p : positions) y = std::min(y, p.y);
  return y;
}

inline float lowest_over_clip(const deform::BoundModel& bound, const motion::ClipPoses& poses) {
  deform::test::Posing posing(bound);
  std::vector<glm::vec3> positions(bound.model.vertex_count());
  const float floor = lowest(bound.model.positions);
  float worst = std::numeric_limits<float>::infinity();
  for (int frame = 0; frame < poses.frame_count(); frame += 10) {
    deform::Pose pose = poses.pose_at_frame(frame);
    posing.deform(pose, deform::DeformMethod::kSweep, positions);
    worst = std::min(worst, lowest(positions) - floor);
  }
  return worst;
}

inline float lowest_over_clip(const deform::BoundModel& bound, const motion::Clip& clip,
                              motion::Feet feet) {
  return lowest_over_clip(bound, motion::Retargeter(clip, bound.model, {}, feet));
}

inline float worst_foot_slide(const motion::Retargeter& r) {
  float worst = 0.0f;
  for (const auto& s : r.foot_planting()->contact_slides([&](int f) { return r.pose_at_frame(f); }))
    worst = std::max(worst, s.slide);
  return worst;
}

}  // namespace sweepd::test
