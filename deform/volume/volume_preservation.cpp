#include "deform/volume/volume_preservation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "deform/binding/rest_sweep.h"
#include "deform/model/joint_turn_from_rest.h"
#include "deform/sweep/swept_volume.h"

namespace sweepd::deform {

bool preserves_volume(BodyPart part, const VolumePreservationOptions& options) {
  switch (part) {
    case BodyPart::kLeftArm:
    case BodyPart::kRightArm:
      return options.arms;
    case BodyPart::kLeftLeg:
    case BodyPart::kRightLeg:
      return options.legs;
    case BodyPart::kTorso:
      return options.torso;
    case BodyPart::kNeck:
      return options.neck;
    default:
      return false;
  }
}

std::vector<double> rest_sweep_volumes(const BoundModel& bound) {
  std::vector<double> volumes;
  for (const BoundSweep& sweep : bound.sweeps)
    volumes.push_back(sweep_volume(rest_sweep(sweep, bound.options)));
  return volumes;
}

VolumePreserver::VolumePreserver(const BoundModel& bound, std::span<const double> rest_volumes)
    : bound_(bound), rest_volume_(rest_volumes) {
  if (rest_volumes.size() != bound.sweeps.size())
    throw std::invalid_argument("volume preservation: " + std::to_string(rest_volumes.size()) +
                                " rest volumes for " + std::to_string(bound.sweeps.size()) +
                                " sweeps");
  std::size_t most_keys = 0;
  for (const BoundSweep& sweep : bound.sweeps)
    most_keys = std::max(most_keys, sweep.rest_keys.size());
  corrections_.resize(bound.sweeps.size());
  turn_.reserve(most_keys);
  for (std::vector<int>* list :
       {&first_controls_, &controls_, &first_alpha_, &first_beta_, &alpha_, &beta_})
    list->reserve(most_keys);
  delta_alpha_.reserve(most_keys);
  delta_beta_.reserve(most_keys);
}

void VolumePreserver::split_axes(const Sweep& sweep, std::span<const int> keys,
                                 const VolumePreservationOptions& options, std::vector<int>& alpha,
                                 std::vector<int>& beta) const {
  alpha.clear();
  beta.clear();
  const std::span<const double> t = sweep.parameters();
  const int last = sweep.key_count() - 1;
  const float threshold = glm::radians(options.bend_plane_degrees);
  for (int k : keys) {
    const glm::quat before = sweep.orientation(static_cast<float>(t[std::max(k - 1, 0)]));
    const glm::quat after = sweep.orientation(static_cast<float>(t[std::min(k + 1, last)]));
    const glm::quat turn = after * glm::conjugate(before);
    const float angle = 2.0f * std::acos(std::min(1.0f, std::abs(turn.w)));
    if (options.bend_plane_degrees < 0.0f || angle < threshold) {
      alpha.push_back(k);
      beta.push_back(k);
      continue;
    }
    // The bend axis; the half-axis more nearly along it is the one across the bend plane.
    const glm::vec3 axis = glm::normalize(glm::vec3(turn.x, turn.y, turn.z));
    const glm::mat3 frame = sweep.rotation(static_cast<float>(t[k]));
    if (std::abs(glm::dot(frame[0], axis)) >= std::abs(glm::dot(frame[1], axis)))
      alpha.push_back(k);
    else
      beta.push_back(k);
  }
}

int VolumePreserver::choose_controls(int s, std::span<const glm::quat> joint_rotation) {
  const BoundSweep& sweep = bound_.sweeps[s];
  const int keys = static_cast<int>(sweep.anchors.size());
  turn_.assign(keys, -1.0f);
  int most = -1;
  for (int k = 0; k < keys; ++k) {
    if (!sweep.anchors[k].is_joint_key()) continue;
    // The skeleton's root turns the whole body, which bends nothing: at rest on the sweep.
    const int joint = sweep.anchors[k].joint;
    turn_[k] = bound_.model.skeleton.joints[joint].parent < 0
                   ? 0.0f
                   : joint_turn_from_rest(bound_.model.skeleton, joint_rotation, joint);
    if (most < 0 || turn_[k] > turn_[most]) most = k;
  }
  if (most < 0) most = keys / 2;  // no joint key: start in the middle
  first_controls_.clear();
  for (int k = 0; k < keys; ++k)
    if (k == most || (turn_[most] > 0.0f && turn_[k] >= 0.5f * turn_[most]))
      first_controls_.push_back(k);
  controls_.clear();
  for (int k = 0; k < keys; ++k) {
    const bool near = std::any_of(first_controls_.begin(), first_controls_.end(),
                                  [k](int c) { return std::abs(c - k) <= 1; });
    if (near) controls_.push_back(k);
  }
  return most;
}

void VolumePreserver::apply(SweepPoser& poser, std::span<const glm::quat> joint_rotation,
                            const VolumePreservationOptions& options,
                            std::span<const double> added_volume) {
  if (!added_volume.empty() && added_volume.size() != bound_.sweeps.size())
    throw std::invalid_argument("volume preservation: " + std::to_string(added_volume.size()) +
                                " added volumes for " + std::to_string(bound_.sweeps.size()) +
                                " sweeps");
  for (int s = 0; s < poser.sweep_count(); ++s) {
    VolumeCorrection& record = corrections_[s];
    record = VolumeCorrection{};
    record.rest_volume = rest_volume_[s];
    if (!preserves_volume(bound_.sweeps[s].part, options)) continue;
    Sweep& sweep = poser.sweep(s);
    record.corrected = true;
    record.target = rest_volume_[s] - (added_volume.empty() ? 0.0 : added_volume[s]);
    record.most_turned_key = choose_controls(s, joint_rotation);
    split_axes(sweep, first_controls_, options, first_alpha_, first_beta_);
    split_axes(sweep, controls_, options, alpha_, beta_);
    delta_alpha_.resize(sweep.key_count());
    delta_beta_.resize(sweep.key_count());
    const double scale = std::abs(rest_volume_[s]);
    double volume = sweep_volume(sweep);
    record.before = volume;
    while (record.iterations < options.max_iterations &&
           std::abs(volume - record.target) >= options.tolerance * scale) {
      const bool neighbours = record.iterations >= options.joint_key_iterations;
      volume_correction_step(sweep, record.target, neighbours ? alpha_ : first_alpha_,
                             neighbours ? beta_ : first_beta_, delta_alpha_, delta_beta_);
      apply_half_axis_deltas(sweep, delta_alpha_, delta_beta_);
      volume = sweep_volume(sweep);
      ++record.iterations;
    }
    record.after = volume;
  }
  poser.refresh_table();
}

}  // namespace sweepd::deform
