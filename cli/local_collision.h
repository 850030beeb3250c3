// LocalCollision: the collision backend of a sweepctl command that deforms here (pose, render,
// positionmap) — where folding finds its intersecting triangle pairs, from --collision
// auto|gpu|cpu and what EGL finds (gpu::choose_collision_backend, gpu/collision_backend.h).
// On gpu it owns a gpu::Context and a gpu::CollisionDetector on the command's thread and gives
// DeformJob that pair finder; on cpu the pair finder is empty (the CPU reference). It adds up
// each deformation's stage times for the command's report.
//
// LocalCollision(choice): probes EGL unless choice is cpu; throws gpu::CollisionBackendError
//   for gpu without a usable EGL context (naming the problem).
// It is the sheet::PairSource of sweepctl's comparing commands (gpu/sheet/deform_with.h).
// begin(): the DeformJob's pair finder (makes the context current first; empty on cpu).
// finish(report): one deformation's stage times (FeatureReport::times, and the GPU detector's
//   upload, readback and dispatch). summary(): "collision: gpu (why); N frames: detect ... ms
//   (upload ..., readback ... of which dispatch ...), fold ... ms, protrude ... ms, contact ...
//   ms" — totals over the frames added (contact: its resolve steps; its detection is in detect).
// describe_collision: that line from its parts (also for a daemon's Stats.collision, where
//   `where` is " on sweepd at HOST:PORT" and `counted` "N poses since it started").
#pragma once

#include <chrono>
#include <optional>
#include <string>

#include "deform/features/collision_features.h"
#include "gpu/collision.h"
#include "gpu/collision_backend.h"
#include "gpu/egl_context.h"
#include "gpu/sheet/deform_with.h"

namespace sweepd::cli {

// Upload and readback are printed on the GPU backend only.
std::string describe_collision(gpu::CollisionBackend backend, const std::string& where,
                               const std::string& reason, const std::string& counted,
                               const deform::FeatureTimes& times,
                               const gpu::CollisionTimings& gpu_times);

class LocalCollision final : public sheet::PairSource {
 public:
  explicit LocalCollision(gpu::CollisionChoice choice);

  const gpu::CollisionBackendDecision& decision() const { return decision_; }
  const deform::DetectPairs& begin() override;
  void finish(const deform::FeatureReport& report) override;
  std::string summary() const;

 private:
  gpu::CollisionBackendDecision decision_;
  std::optional<gpu::Context> context_;
  std::optional<gpu::CollisionDetector> detector_;
  deform::DetectPairs detect_;
  int frames_ = 0;
  deform::FeatureTimes times_;
  gpu::CollisionTimings gpu_times_, frame_gpu_times_;  // totals; this frame's so far
};

}  // namespace sweepd::cli
