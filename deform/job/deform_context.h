// DeformContext: the per-thread scratch of DeformJob::run (deform_job.h) — ozz-animation's
// per-instance context. One per thread that deforms (a server worker, a CLI, a test); it serves
// any model, re-binding its scratch when a job names another ModelRuntime (which allocates; the
// same model again allocates nothing). Not shared between threads.
//
// Holds: the world pose and skinning matrices (J each), the sweep poser's per-frame state
//   (posed keys and sweeps, sample table), the volume preserver's scratch, the collision
//   features' scratch, the welded-normal sums, and — for a stream of frames of one model
//   (VolumeChangeSource::kPreviousFrame) — the I_C the features measured in the previous frame.
// After a run: world_pose(), skinning(), sweep_poser() (posed by sweep runs),
//   volume_corrections() (empty when volume preservation was off), measured_volume_change()
//   (per sweep, what folding and protrusion added: the next stream frame's I_C).
// sweep_poser() exists once the context is bound to a model (prepare or a run).
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <optional>
#include <span>
#include <vector>

#include "deform/features/collision_features.h"
#include "deform/features/muscle_bulge.h"
#include "deform/job/model_runtime.h"
#include "deform/posing/sweep_poser.h"
#include "deform/volume/volume_preservation.h"

namespace sweepd::deform {

struct DeformJob;

class DeformContext {
 public:
  DeformContext() = default;
  DeformContext(const DeformContext&) = delete;  // the poser's key adjuster points at this
  DeformContext& operator=(const DeformContext&) = delete;

  // Binds the scratch to `runtime` (DeformJob::run calls it). A new runtime ends the stream.
  void prepare(const ModelRuntime& runtime);

  std::span<const glm::mat4> world_pose() const { return world_pose_; }
  std::span<const glm::mat4> skinning() const { return skinning_; }
  SweepPoser& sweep_poser() { return *poser_; }
  const SweepPoser& sweep_poser() const { return *poser_; }
  std::span<const VolumeCorrection> volume_corrections() const { return corrections_; }
  std::span<const double> measured_volume_change() const { return measured_; }

 private:
  friend struct DeformJob;

  std::uint64_t serial_ = 0;  // the runtime the scratch is bound to (0: none)
  const ModelRuntime* runtime_ = nullptr;
  std::vector<glm::mat4> world_pose_, skinning_;
  std::optional<SweepPoser> poser_;
  std::optional<VolumePreserver> volume_;
  std::optional<CollisionFeatures> collision_;
  std::vector<FloatLanes> normal_sums_;
  std::span<const VolumeCorrection> corrections_;
  // Per sweep: I_C of the volume target (the features' change), the target's I_C with the
  // caller's added volume, and the features' measured change of the last frame.
  std::vector<double> volume_change_, target_change_, measured_;
  bool stream_ = false;  // measured_ holds the previous frame of a stream of this model
  // What the key adjuster applies in set_pose (the running job's, kept for later set_pose
  // calls on sweep_poser()).
  bool edits_ = true, bulge_ = false;
  MuscleBulgeOptions bulge_options_;
};

}  // namespace sweepd::deform
