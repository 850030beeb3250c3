#include "motion/own_skeleton_clip.h"

#include <stdexcept>
#include <string>
#include <vector>

namespace sweepd::motion {
namespace {

deform::Pose pose_of(std::vector<glm::quat> rotations, const std::vector<glm::vec3>& translations) {
  deform::Pose pose;
  pose.local_rotations = std::move(rotations);
  pose.root_translation = translations[0];
  return pose;
}

}  // namespace

OwnSkeletonClip::OwnSkeletonClip(Clip clip, const deform::Skeleton& skeleton)
    : OwnSkeletonClip(std::make_shared<const Clip>(std::move(clip)), skeleton) {}

OwnSkeletonClip::OwnSkeletonClip(std::shared_ptr<const Clip> clip,
                                 const deform::Skeleton& skeleton)
    : clip_(std::move(clip)) {
  if (clip_->joints.size() != skeleton.joints.size())
    throw std::invalid_argument("the clip animates " + std::to_string(clip_->joints.size()) +
                                " joints, the model has " + std::to_string(skeleton.joints.size()) +
                                ": not the model's own skeleton");
  for (std::size_t j = 0; j < skeleton.joints.size(); ++j)
    if (clip_->joints[j].name != skeleton.joints[j].name ||
        clip_->joints[j].parent != skeleton.joints[j].parent)
      throw std::invalid_argument("the clip's joint " + std::to_string(j) + " is '" +
                                  clip_->joints[j].name + "', the model's '" +
                                  skeleton.joints[j].name + "': not the model's own skeleton");
  if (clip_->frame_count < 1) throw std::invalid_argument("the clip has no frames");
}

deform::Pose OwnSkeletonClip::pose_at_frame(int frame) const {
  if (frame < 0 || frame >= clip_->frame_count)
    throw std::out_of_range("frame " + std::to_string(frame) + " is outside the clip's " +
                            std::to_string(clip_->frame_count) + " frames");
  std::vector<glm::quat> rotations(clip_->joints.size());
  std::vector<glm::vec3> translations(clip_->joints.size());
  clip_->local_pose(frame, rotations, translations);
  return pose_of(std::move(rotations), translations);
}

deform::Pose OwnSkeletonClip::pose_at_time(double seconds) const {
  std::vector<glm::quat> rotations(clip_->joints.size());
  std::vector<glm::vec3> translations(clip_->joints.size());
  clip_->local_pose_at_time(seconds, rotations, translations);
  return pose_of(std::move(rotations), translations);
}

}  // namespace sweepd::motion
