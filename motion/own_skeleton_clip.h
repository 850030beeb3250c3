// OwnSkeletonClip: a clip that animates the model's own skeleton (a glTF animation read from the
// model's file with io/gltf/gltf_clip_load.h, whose joints are the same skin's joints in the same
// order), played joint for joint with no retargeting: each model joint takes its clip joint's
// local rotation, and the root translation is the clip's root translation.
//
// Input:  clip      J clip joints, named as the skeleton's, in the same order
//         skeleton  the model's skeleton (J joints)
// Output: deform::Poses (motion/clip_poses.h). Throws std::invalid_argument naming the first
//         joint that differs when the clip's joints are not the skeleton's.
#pragma once

#include <memory>

#include "deform/model/skeleton.h"
#include "motion/clip_poses.h"

namespace sweepd::motion {

class OwnSkeletonClip final : public ClipPoses {
 public:
  OwnSkeletonClip(Clip clip, const deform::Skeleton& skeleton);
  // A clip shared with other players: the frames are not copied.
  OwnSkeletonClip(std::shared_ptr<const Clip> clip, const deform::Skeleton& skeleton);
  const Clip& motion() const override { return *clip_; }
  deform::Pose pose_at_frame(int frame) const override;
  deform::Pose pose_at_time(double seconds) const override;

 private:
  std::shared_ptr<const Clip> clip_;  // never null
};

}  // namespace sweepd::motion
