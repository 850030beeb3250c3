#include "deform/job/deformer.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "deform/baselines/dual_quaternion_skinning.h"
#include "deform/baselines/linear_blend_skinning.h"
#include "deform/model/forward_kinematics.h"

namespace sweepd::deform {

const char* to_string(DeformMethod method) {
  switch (method) {
    case DeformMethod::kSweep:
      return "sweep";
    case DeformMethod::kLbs:
      return "lbs";
    case DeformMethod::kDqs:
      return "dqs";
  }
  return "?";
}

std::optional<DeformMethod> parse_deform_method(std::string_view name) {
  for (DeformMethod m : {DeformMethod::kSweep, DeformMethod::kLbs, DeformMethod::kDqs})
    if (name == to_string(m)) return m;
  return std::nullopt;
}

Deformer::Deformer(const BoundModel& bound)
    : bound_(bound),
      sweep_poser_(bound),
      volume_preserver_(bound),
      world_rest_inverse_(world_rest_inverse_matrices(bound.model.skeleton)),
      world_pose_(bound.model.skeleton.joints.size()),
      skinning_(bound.model.skeleton.joints.size()) {
  if (!bound.edits.edits.empty()) set_edits(bound.edits);
  sweep_poser_.set_key_adjuster([this](int sweep, std::span<KeyEllipse> keys) {
    const auto rotations = sweep_poser_.joint_rotations();
    if (options_.edits && !edits_.edits.empty())
      apply_key_ellipse_edits(edits_, bound_, sweep, rotations, keys);
    if (options_.muscle_bulge) apply_muscle_bulge(bound_, sweep, rotations, options_.bulge, keys);
  });
}

void Deformer::set_edits(KeyEllipseEdits edits) {
  if (std::string why = validate(edits, bound_); !why.empty())
    throw std::invalid_argument("key ellipse edits: " + why);
  edits_ = std::move(edits);
}

void Deformer::deform(Pose& pose, DeformMethod method, std::span<glm::vec3> positions,
                      std::span<glm::vec3> normals, int threads) {
  const Model& model = bound_.model;
  if (std::string why = normalize_and_validate(pose, model.skeleton); !why.empty())
    throw std::invalid_argument("invalid pose: " + why);
  if (positions.size() != model.vertex_count() ||
      (!normals.empty() && normals.size() != model.vertex_count()))
    throw std::invalid_argument("output buffers must hold " + std::to_string(model.vertex_count()) +
                                " vertices");
  forward_kinematics(model.skeleton, pose, world_pose_);
  skinning_matrices(world_pose_, world_rest_inverse_, skinning_);
  switch (method) {
    case DeformMethod::kSweep:
      sweep_poser_.set_pose(world_pose_);
      if (options_.preserve_volume) {
        deform_preserving_volume(positions, normals, threads);
      } else {
        sweep_poser_.deform(skinning_, positions, normals, threads);
      }
      break;
    case DeformMethod::kLbs:
      linear_blend_skinning_parallel(model, skinning_, positions, normals, threads);
      break;
    case DeformMethod::kDqs:
      dual_quaternion_skinning_parallel(model, skinning_, positions, normals, threads);
      break;
  }
}

void Deformer::deform_preserving_volume(std::span<glm::vec3> positions,
                                        std::span<glm::vec3> normals, int threads) {
  const VolumePreservationOptions& volume = options_.volume;
  const std::size_t sweeps = bound_.sweeps.size();
  if (!options_.added_volume.empty() && options_.added_volume.size() != sweeps)
    throw std::invalid_argument(
        "volume preservation: " + std::to_string(options_.added_volume.size()) +
        " added volumes for " + std::to_string(sweeps) + " sweeps");
  added_volume_.assign(sweeps, 0.0);
  if (!options_.added_volume.empty()) added_volume_ = options_.added_volume;
  fold_volume_.assign(sweeps, 0.0);
  fold_iterations_ = 0;
  volume_preserver_.apply(sweep_poser_, sweep_poser_.joint_rotations(), volume, added_volume_);
  if (volume.fold_feedback_iterations > 0 && !regions_) {
    regions_.emplace(bound_);
    for (std::size_t s = 0; s < sweeps; ++s)
      rest_region_volume_.push_back(regions_->volume(static_cast<int>(s), bound_.model.positions));
  }
  for (int round = 0; round < volume.fold_feedback_iterations; ++round) {
    sweep_poser_.deform(skinning_, positions, {}, threads);
    bool changed = false;
    for (std::size_t s = 0; s < sweeps; ++s) {
      if (!preserves_volume(bound_.sweeps[s].part, volume) || rest_region_volume_[s] <= 0.0)
        continue;
      const double change =
          regions_->volume(static_cast<int>(s), positions) / rest_region_volume_[s] - 1.0;
      // Folding only loses volume: a region that grew (where parts blend, e.g. a raised arm
      // stretching the torso's shoulder zone) is left alone rather than shrunk as a whole.
      if (change > -volume.mesh_tolerance) continue;
      // The region lost `change` while the sweep holds its target: folding's share, in the
      // sweep's units, lowers I_C (raises the target) by as much.
      const double fold = change * volume_preserver_.rest_volume(static_cast<int>(s));
      fold_volume_[s] += fold;
      added_volume_[s] += fold;
      changed = true;
    }
    if (!changed) break;
    ++fold_iterations_;
    volume_preserver_.apply(sweep_poser_, sweep_poser_.joint_rotations(), volume, added_volume_);
  }
  sweep_poser_.deform(skinning_, positions, normals, threads);
}

}  // namespace sweepd::deform
