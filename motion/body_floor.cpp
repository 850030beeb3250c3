#include "motion/body_floor.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "deform/model/forward_kinematics.h"

namespace sweepd::motion {

BodyFloor BodyFloor::build(const deform::Model& model,
                           std::shared_ptr<const BodySamples> samples_in,
                           const std::vector<bool>& feet, float floor, int frame_count,
                           double frame_time, const std::function<deform::Pose(int)>& frame_pose,
                           std::span<const int> group) {
  BodyFloor body;
  body.frame_time_ = frame_time;
  body.lift_.assign(std::max(frame_count, 1), 0.0f);
  body.samples_ = std::move(samples_in);
  const BodySamples& samples = *body.samples_;
  std::vector<float> lowest_allowed;
  std::vector<int> group_of;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const int joint = samples.joint(i);
    lowest_allowed.push_back(feet.at(joint) ? floor - kSoleTolerance : floor + kClearance);
    group_of.push_back(group.empty() ? -1 : group[i]);
    body.groups_ = std::max(body.groups_, group_of.back() + 1);
  }
  if (samples.size() == 0 || frame_count < 1) return body;
  body.lowest_.assign(static_cast<std::size_t>(frame_count) * body.groups_, Lowest{});
  const std::vector<glm::mat4> rest_inverse = deform::world_rest_inverse_matrices(model.skeleton);
  std::vector<glm::mat4> world(model.skeleton.size()), skinning(model.skeleton.size());
  std::vector<float> need(frame_count, 0.0f);
  for (int f = 0; f < frame_count; ++f) {
    deform::forward_kinematics(model.skeleton, frame_pose(f), world);
    deform::skinning_matrices(world, rest_inverse, skinning);
    Lowest* lowest = body.lowest_.data() + static_cast<std::size_t>(f) * body.groups_;
    float deepest = 0.0f;
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const float y = samples.height(i, skinning);
      deepest = std::max(deepest, lowest_allowed[i] - samples.swept_height(i, skinning));
      if (const int g = group_of[i]; g >= 0 && y - floor < lowest[g].height)
        lowest[g] = {y - floor, static_cast<int>(i)};
    }
    need[f] = deepest;
  }
  // Each need spreads kEase either side, falling linearly: the lift is their upper envelope.
  const int reach = std::max(1, static_cast<int>(std::ceil(kEase / frame_time)));
  for (int f = 0; f < frame_count; ++f) {
    if (need[f] <= 0.0f) continue;
    for (int g = std::max(0, f - reach); g <= std::min(frame_count - 1, f + reach); ++g) {
      const double gap = std::abs(g - f) * frame_time;
      const float share = static_cast<float>(std::max(0.0, 1.0 - gap / kEase));
      body.lift_[g] = std::max(body.lift_[g], need[f] * share);
    }
  }
  return body;
}

BodyFloor::Lowest BodyFloor::lowest(int group, int frame) const {
  Lowest low = lowest_.at(static_cast<std::size_t>(frame) * groups_ + group);
  low.height += lift_[frame];
  return low;
}

void BodyFloor::apply(double seconds, deform::Pose& pose) const {
  const int last = static_cast<int>(lift_.size()) - 1;
  const double position = std::clamp(seconds / frame_time_, 0.0, static_cast<double>(last));
  const int f0 = static_cast<int>(std::floor(position));
  const int f1 = std::min(f0 + 1, last);
  pose.root_translation.y += glm::mix(lift_[f0], lift_[f1], static_cast<float>(position - f0));
}

float BodyFloor::largest_lift() const {
  return lift_.empty() ? 0.0f : *std::max_element(lift_.begin(), lift_.end());
}

}  // namespace sweepd::motion
