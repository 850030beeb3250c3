#include "cli/local_collision.h"

#include <cstdio>

namespace sweepd::cli {
namespace {

double milliseconds(std::chrono::nanoseconds time) {
  return std::chrono::duration<double, std::milli>(time).count();
}

}  // namespace

LocalCollision::LocalCollision(gpu::CollisionChoice choice) {
  gpu::EglDevice device;
  if (choice != gpu::CollisionChoice::kCpu) {
    try {
      context_.emplace();
      device.renderer = context_->renderer();
      device.software = gpu::is_software_renderer(context_->renderer(), context_->software());
    } catch (const gpu::ContextError& error) {
      device.failure = error.what();
    }
  }
  decision_ = gpu::choose_collision_backend(choice, device);
  if (decision_.backend == gpu::CollisionBackend::kCpu) {
    context_.reset();  // probed only (auto on llvmpipe)
    return;
  }
  detector_.emplace(*context_);
  detect_ = [this](std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                   std::span<const std::uint32_t> triangles,
                   std::vector<deform::TrianglePair>& pairs) {
    detector_->detect(positions, indices, triangles, pairs);
    frame_gpu_times_.upload += detector_->last_timings().upload;
    frame_gpu_times_.readback += detector_->last_timings().readback;
  };
}

const deform::DetectPairs& LocalCollision::detect() {
  // Another context (sweepctl render's preview) may have been made current since.
  if (context_) context_->make_current();
  frame_gpu_times_ = {};
  return detect_;
}

void LocalCollision::add(const deform::FeatureReport& report) {
  ++frames_;
  times_ += report.times;
  gpu_times_.upload += frame_gpu_times_.upload;
  gpu_times_.readback += frame_gpu_times_.readback;
  frame_gpu_times_ = {};
}

std::string LocalCollision::summary() const {
  char text[256];
  const bool on_gpu = decision_.backend == gpu::CollisionBackend::kGpu;
  char gpu_part[96] = "";
  if (on_gpu) {
    std::snprintf(gpu_part, sizeof gpu_part, " (upload %.1f, readback %.1f)",
                  milliseconds(gpu_times_.upload), milliseconds(gpu_times_.readback));
  }
  std::snprintf(text, sizeof text, "%d frame%s: detect %.1f ms%s, fold %.1f ms, protrude %.1f ms",
                frames_, frames_ == 1 ? "" : "s", milliseconds(times_.detect), gpu_part,
                milliseconds(times_.fold), milliseconds(times_.protrude));
  return std::string("collision: ") + gpu::to_string(decision_.backend) + " (" + decision_.reason +
         "); " + text;
}

}  // namespace sweepd::cli
