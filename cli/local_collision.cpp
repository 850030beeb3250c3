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
    frame_gpu_times_.dispatch += detector_->last_timings().dispatch;
  };
}

const deform::DetectPairs& LocalCollision::begin() {
  // Another context (sweepctl render's preview) may have been made current since.
  if (context_) context_->make_current();
  frame_gpu_times_ = {};
  return detect_;
}

void LocalCollision::finish(const deform::FeatureReport& report) {
  ++frames_;
  times_ += report.times;
  gpu_times_.upload += frame_gpu_times_.upload;
  gpu_times_.readback += frame_gpu_times_.readback;
  gpu_times_.dispatch += frame_gpu_times_.dispatch;
  frame_gpu_times_ = {};
}

std::string describe_collision(gpu::CollisionBackend backend, const std::string& where,
                               const std::string& reason, const std::string& counted,
                               const deform::FeatureTimes& times,
                               const gpu::CollisionTimings& gpu_times) {
  char gpu_part[96] = "";
  if (backend == gpu::CollisionBackend::kGpu) {
    std::snprintf(gpu_part, sizeof gpu_part, " (upload %.1f, readback %.1f of which dispatch %.1f)",
                  milliseconds(gpu_times.upload), milliseconds(gpu_times.readback),
                  milliseconds(gpu_times.dispatch));
  }
  char stages[256];
  std::snprintf(stages, sizeof stages,
                ": detect %.1f ms%s, fold %.1f ms, protrude %.1f ms, contact %.1f ms",
                milliseconds(times.detect), gpu_part, milliseconds(times.fold),
                milliseconds(times.protrude), milliseconds(times.contact));
  return std::string("collision") + where + ": " + gpu::to_string(backend) + " (" + reason + "); " +
         counted + stages;
}

std::string LocalCollision::summary() const {
  return describe_collision(decision_.backend, "", decision_.reason,
                            std::to_string(frames_) + (frames_ == 1 ? " frame" : " frames"), times_,
                            gpu_times_);
}

}  // namespace sweepd::cli
