#include "deform/job/deform_context.h"

namespace sweepd::deform {

void DeformContext::prepare(const ModelRuntime& runtime) {
  if (serial_ == runtime.serial()) return;
  const BoundModel& bound = runtime.bound();
  const std::size_t joints = bound.model.skeleton.joints.size();
  const std::size_t sweeps = bound.sweeps.size();
  world_pose_.assign(joints, glm::mat4(1.0f));
  skinning_.assign(joints, glm::mat4(1.0f));
  collision_.reset();
  volume_.reset();
  poser_.reset();
  runtime_ = &runtime;
  poser_.emplace(runtime.poser_tables());
  poser_->set_key_adjuster([this](int sweep, std::span<KeyEllipse> keys) {
    const BoundModel& model = runtime_->bound();
    const auto rotations = poser_->joint_rotations();
    if (edits_ && !runtime_->edits().edits.empty())
      apply_key_ellipse_edits(runtime_->edits(), model, sweep, rotations, keys);
    if (bulge_) apply_muscle_bulge(model, sweep, rotations, bulge_options_, keys);
  });
  volume_.emplace(bound, runtime.rest_volumes());
  collision_.emplace(runtime.collision());
  corrections_ = {};
  volume_change_.assign(sweeps, 0.0);
  target_change_.assign(sweeps, 0.0);
  measured_.assign(sweeps, 0.0);
  stream_ = false;
  serial_ = runtime.serial();
}

}  // namespace sweepd::deform
