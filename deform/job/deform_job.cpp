#include "deform/job/deform_job.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "deform/baselines/dual_quaternion_skinning.h"
#include "deform/baselines/linear_blend_skinning.h"
#include "deform/model/forward_kinematics.h"

namespace sweepd::deform {

namespace {

// Whether the measured I_C is within the volume tolerance (× I0) of the one targeted, on every
// corrected sweep: the fixed point is reached.
bool settled(std::span<const double> measured, std::span<const double> targeted,
             std::span<const double> rest_volumes, const BoundModel& bound,
             const VolumePreservationOptions& options) {
  for (std::size_t s = 0; s < measured.size(); ++s)
    if (preserves_volume(bound.sweeps[s].part, options) &&
        std::abs(measured[s] - targeted[s]) >= options.tolerance * std::abs(rest_volumes[s]))
      return false;
  return true;
}

}  // namespace

JobProblem DeformJob::validate() {
  const BoundModel& bound = runtime.bound();
  const Skeleton& skeleton = bound.model.skeleton;
  if (pose.local_rotations.size() != skeleton.joints.size())
    return {JobProblem::Input::kJointCount,
            "invalid pose: the pose has " + std::to_string(pose.local_rotations.size()) +
                " rotations, the skeleton " + std::to_string(skeleton.joints.size()) + " joints"};
  if (std::string why = normalize_and_validate(pose, skeleton, options.rotation_length_tolerance);
      !why.empty())
    return {JobProblem::Input::kPose, "invalid pose: " + why};
  if (features.any() && method != DeformMethod::kSweep)
    return {JobProblem::Input::kSelection, "features (" + to_string(features) +
                                               ") apply to the sweep method only, not " +
                                               to_string(method)};
  if (!options.added_volume.empty() && options.added_volume.size() != bound.sweeps.size())
    return {JobProblem::Input::kSelection,
            "volume preservation: " + std::to_string(options.added_volume.size()) +
                " added volumes for " + std::to_string(bound.sweeps.size()) + " sweeps"};
  return {};
}

DeformReport DeformJob::run(DeformContext& context) {
  if (JobProblem problem = validate()) throw std::invalid_argument(problem.message);
  return run_validated(context);
}

DeformReport DeformJob::run_validated(DeformContext& context) {
  const Model& model = runtime.bound().model;
  if (pose.local_rotations.size() != model.skeleton.joints.size())
    throw std::invalid_argument(
        "run_validated: the pose has " + std::to_string(pose.local_rotations.size()) +
        " rotations, the skeleton " + std::to_string(model.skeleton.joints.size()) + " joints");
  if (positions.size() != model.vertex_count() ||
      (!normals.empty() && normals.size() != model.vertex_count()))
    throw std::invalid_argument("output buffers must hold " + std::to_string(model.vertex_count()) +
                                " vertices");
  context.prepare(runtime);
  context.edits_ = options.edits;
  context.bulge_ = features.bulge;
  context.bulge_options_ = options.bulge;
  context.corrections_ = {};
  forward_kinematics(model.skeleton, pose, context.world_pose_);
  skinning_matrices(context.world_pose_, runtime.world_rest_inverse(), context.skinning_);
  DeformReport report;
  switch (method) {
    case DeformMethod::kSweep:
      context.poser_->set_pose(context.world_pose_);
      run_sweep(context, report);
      break;
    case DeformMethod::kLbs:
      linear_blend_skinning(runtime.skinning_table(), context.skinning_, positions, normals,
                            options.threads);
      report.rounds = 1;
      break;
    case DeformMethod::kDqs:
      dual_quaternion_skinning(runtime.skinning_table(), context.skinning_, positions, normals,
                               options.threads);
      report.rounds = 1;
      break;
  }
  if (method == DeformMethod::kSweep) report.volume_change = context.volume_change_;
  report.corrections = context.corrections_;
  return report;
}

void DeformJob::run_sweep(DeformContext& context, DeformReport& report) {
  SweepPoser& poser = *context.poser_;
  CollisionFeatures& collision = *context.collision_;
  const bool collide = features.collision();
  if (collide) {
    collision.set_options(options.collision);
    collision.select(features.folding, features.protrusion, features.contact);
  }
  std::vector<double>& change = context.volume_change_;  // I_C targeted
  const bool from_stream =
      options.volume_change == VolumeChangeSource::kPreviousFrame && context.stream_ && collide;
  if (from_stream) {
    change = context.measured_;
  } else {
    std::fill(change.begin(), change.end(), 0.0);
  }
  // With volume and a collision feature, I_C comes from the features: one deformation in a
  // stream, else up to fixed_point_rounds. Otherwise I_C is 0 (and the caller's) and one
  // deformation does.
  const int rounds =
      features.volume && collide && !from_stream ? std::max(1, options.fixed_point_rounds) : 1;
  for (int round = 0; round < rounds; ++round) {
    if (features.volume) {
      for (std::size_t s = 0; s < change.size(); ++s)
        context.target_change_[s] =
            change[s] + (options.added_volume.empty() ? 0.0 : options.added_volume[s]);
      context.volume_->apply(poser, poser.joint_rotations(), options.volume,
                             context.target_change_);
      context.corrections_ = context.volume_->last_corrections();
    }
    poser.deform(context.skinning_, positions, {}, options.threads);
    report.rounds = round + 1;
    if (!collide) break;
    const auto started = std::chrono::steady_clock::now();
    const FeatureTimes earlier_rounds = report.features.times;
    report.features = collision.apply(context.skinning_, positions, options.detect);
    report.features.times += earlier_rounds;
    report.features_time += std::chrono::steady_clock::now() - started;
    const std::span<const double> measured = collision.sweep_volume_change();
    if (round + 1 == rounds ||
        settled(measured, change, runtime.rest_volumes(), runtime.bound(), options.volume))
      break;
    std::copy(measured.begin(), measured.end(), change.begin());
  }
  if (collide) {
    const std::span<const double> measured = collision.sweep_volume_change();
    std::copy(measured.begin(), measured.end(), context.measured_.begin());
    context.stream_ = true;
  }
  if (!normals.empty())
    runtime.welded_normals().compute(positions, normals, context.normal_sums_, options.threads);
}

}  // namespace sweepd::deform
