#include "server/services/collision_service.h"

#include "server/log_event.h"

namespace sweepd::server {
namespace {

constexpr std::size_t kMostLoggedReasons = 64;  // distinct fallback reasons logged at most

std::uint64_t count_ns(std::chrono::nanoseconds time) {
  return static_cast<std::uint64_t>(std::max<std::int64_t>(0, time.count()));
}

}  // namespace

CollisionService::CollisionService(GpuThread& gpu, gpu::CollisionBackendDecision decision,
                                   GpuPairFinder gpu_pairs)
    : gpu_(gpu), decision_(std::move(decision)), gpu_pairs_(std::move(gpu_pairs)) {
  if (decision_.backend == gpu::CollisionBackend::kGpu) {
    if (const gpu::Worker* worker = gpu_.start()) device_ = worker->renderer();
  }
  if (!gpu_pairs_) {
    gpu_pairs_ = [this](gpu::Context& context, std::span<const glm::vec3> positions,
                        std::span<const std::uint32_t> indices,
                        std::span<const std::uint32_t> triangles,
                        std::vector<deform::TrianglePair>& pairs) {
      if (!detector_) detector_ = std::make_unique<gpu::CollisionDetector>(context);
      detector_->detect(positions, indices, triangles, pairs);
      return detector_->last_timings();
    };
  }
}

CollisionService::~CollisionService() {
  // GL objects go with the context, on the worker's thread, before the worker ends.
  if (detector_) gpu_.start()->submit([this](gpu::Context&) { detector_.reset(); }).get();
}

CollisionSnapshot CollisionService::snapshot() const {
  return {.backend = decision_.backend,
          .reason = decision_.reason,
          .device = device_,
          .requests = requests_.load(),
          .gpu_fallbacks = gpu_fallbacks_.load(),
          .detect_ns = detect_ns_.load(),
          .fold_ns = fold_ns_.load(),
          .protrude_ns = protrude_ns_.load(),
          .upload_ns = upload_ns_.load(),
          .readback_ns = readback_ns_.load(),
          .contact_ns = contact_ns_.load(),
          .dispatch_ns = dispatch_ns_.load()};
}

gpu::CollisionTimings CollisionService::detect_on_gpu(std::span<const glm::vec3> positions,
                                                      std::span<const std::uint32_t> indices,
                                                      std::span<const std::uint32_t> triangles,
                                                      std::vector<deform::TrianglePair>& pairs) {
  gpu::Worker* worker = gpu_.start();
  if (worker == nullptr) throw std::runtime_error("no GPU thread: " + gpu_.failure());
  // The job's references outlive it: the caller waits for its result here.
  return worker
      ->submit([&](gpu::Context& context) {
        return gpu_pairs_(context, positions, indices, triangles, pairs);
      })
      .get();
}

void CollisionService::count_fallback(const std::string& reason) {
  ++gpu_fallbacks_;
  std::lock_guard lock(logged_mutex_);
  if (logged_reasons_.size() >= kMostLoggedReasons || !logged_reasons_.insert(reason).second)
    return;
  log_event("collision_gpu_fallback",
            {{"reason", reason},
             {"action",
              "the pose is answered with the CPU reference's pairs; this reason is "
              "logged once, every fallback is counted"}});
}

void CollisionService::count_request(const deform::FeatureTimes& times,
                                     const gpu::CollisionTimings& gpu) {
  ++requests_;
  detect_ns_ += count_ns(times.detect);
  fold_ns_ += count_ns(times.fold);
  protrude_ns_ += count_ns(times.protrude);
  upload_ns_ += count_ns(gpu.upload);
  readback_ns_ += count_ns(gpu.readback);
  contact_ns_ += count_ns(times.contact);
  dispatch_ns_ += count_ns(gpu.dispatch);
}

CollisionPairFinder::CollisionPairFinder(CollisionService& service) : service_(service) {
  if (service.backend() == gpu::CollisionBackend::kGpu) {
    detect_ = [this](std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                     std::span<const std::uint32_t> triangles,
                     std::vector<deform::TrianglePair>& pairs) {
      detect(positions, indices, triangles, pairs);
    };
  }
}

const deform::DetectPairs& CollisionPairFinder::begin() {
  fell_back_ = false;
  gpu_timings_ = {};
  return detect_;
}

void CollisionPairFinder::finish(const deform::FeatureReport& report) {
  service_.count_request(report.times, gpu_timings_);
}

void CollisionPairFinder::detect(std::span<const glm::vec3> positions,
                                 std::span<const std::uint32_t> indices,
                                 std::span<const std::uint32_t> triangles,
                                 std::vector<deform::TrianglePair>& pairs) {
  if (!fell_back_) {
    try {
      const gpu::CollisionTimings timings =
          service_.detect_on_gpu(positions, indices, triangles, pairs);
      gpu_timings_.upload += timings.upload;
      gpu_timings_.readback += timings.readback;
      gpu_timings_.dispatch += timings.dispatch;
      return;
    } catch (const std::exception& error) {
      fell_back_ = true;
      service_.count_fallback(error.what());
    }
  }
  cpu_.detect(positions, indices, triangles, pairs);
}

}  // namespace sweepd::server
