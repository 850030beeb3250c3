// GpuThread: the server's one GPU thread (gpu::Worker, which owns the EGL context), shared by
// position maps (PositionMapService) and collision detection (CollisionService). Started by
// the first start() — at start-up when the collision backend needs EGL, else by the first
// position map — and never again once that failed: the failure is kept and reported.
//
// start(): thread-safe; the worker, or nullptr with failure() saying why EGL gave no context.
// device(): the GL_RENDERER and software flag of the started worker, or the failure, for
//   gpu::choose_collision_backend.
// Services that keep GL objects on the worker must destroy them with a job before this object
// goes (declare it first).
#pragma once

#include <memory>
#include <mutex>
#include <string>

#include "gpu/collision_backend.h"
#include "gpu/gpu_worker.h"

namespace sweepd::server {

class GpuThread {
 public:
  gpu::Worker* start();
  std::string failure() const;
  gpu::EglDevice device();

 private:
  mutable std::mutex mutex_;
  std::unique_ptr<gpu::Worker> worker_;
  std::string failure_;
};

}  // namespace sweepd::server
