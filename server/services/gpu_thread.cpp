#include "server/services/gpu_thread.h"

namespace sweepd::server {

gpu::Worker* GpuThread::start() {
  std::lock_guard lock(mutex_);
  if (!worker_ && failure_.empty()) {
    try {
      worker_ = std::make_unique<gpu::Worker>();
    } catch (const std::exception& error) {
      failure_ = error.what();
    }
  }
  return worker_.get();
}

std::string GpuThread::failure() const {
  std::lock_guard lock(mutex_);
  return failure_;
}

gpu::EglDevice GpuThread::device() {
  const gpu::Worker* worker = start();
  gpu::EglDevice device;
  if (worker == nullptr) {
    device.failure = failure();
  } else {
    device.renderer = worker->renderer();
    device.software = gpu::is_software_renderer(worker->renderer(), worker->software());
  }
  return device;
}

}  // namespace sweepd::server
