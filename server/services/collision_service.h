// CollisionService: the daemon's collision backend (--collision, gpu::CollisionBackend) and
// its counters; CollisionPairFinder: folding's pair finder for the poses of one connection.
//
// On the GPU backend each detection call of a pose (CollisionFeatures calls its pair finder
// per region and per folding round) is one job on the server's GPU thread (GpuThread, the
// thread that renders position maps), run by a gpu::CollisionDetector that lives on that
// thread; the pose's deformation worker waits for that job's result only. The GPU thread runs
// jobs one at a time, so a pose waits behind other connections' GPU jobs, never behind their
// CPU work: poses whose features go to the GPU run on their own thread pool (Server), so the
// deformation workers stay free for every other request while they wait.
// A GPU job that throws: that pose's pairs come from the CPU reference from then on (the same
// pairs: gpu::CollisionDetector finds exactly the CPU reference's pairs, tested pair for pair,
// so the reply equals the CPU backend's),
// the failure is counted (gpu_fallbacks) and logged once per distinct reason
// (`collision_gpu_fallback`). On the CPU backend the pair finder is empty (CollisionFeatures'
// own CPU reference).
//
// CollisionService(gpu, decision, gpu_pairs): `gpu` must outlive it; `gpu_pairs`, when given,
//   replaces gpu::CollisionDetector on the GPU thread (tests inject a failing one).
// snapshot(): thread-safe copy of the backend, its reason and device, and the counters:
//   requests with folding or protrusion, GPU fallbacks, and per-stage totals (ns): detect
//   (the pair finder as the pose saw it: queueing on the GPU thread included), fold, protrude,
//   contact (its resolve steps; its detection is in detect), upload, readback and dispatch
//   (gpu::CollisionTimings, dispatch a part of readback; GPU backend only).
// CollisionPairFinder::begin(): the DeformJob's pair finder for one pose (empty on the CPU
//   backend); finish(report): counts the pose. One per connection (and per contact sheet: it is
//   the sheet::PairSource of its sweep+features cells), used by one pose at a time; no
//   allocation per pose once warm.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <set>
#include <string>

#include "deform/features/collision_features.h"
#include "deform/features/self_intersection.h"
#include "gpu/collision.h"
#include "gpu/collision_backend.h"
#include "gpu/sheet/deform_with.h"
#include "server/services/gpu_thread.h"

namespace sweepd::server {

// Finds a region's pairs on the GPU thread (gpu::CollisionDetector's contract).
using GpuPairFinder = std::function<gpu::CollisionTimings(
    gpu::Context& context, std::span<const glm::vec3> positions,
    std::span<const std::uint32_t> indices, std::span<const std::uint32_t> triangles,
    std::vector<deform::TrianglePair>& pairs)>;

struct CollisionSnapshot {
  gpu::CollisionBackend backend = gpu::CollisionBackend::kCpu;
  std::string reason;  // why this backend (the start-up decision)
  std::string device;  // GL_RENDERER of the GPU thread; empty without one
  std::uint64_t requests = 0, gpu_fallbacks = 0;
  std::uint64_t detect_ns = 0, fold_ns = 0, protrude_ns = 0, upload_ns = 0, readback_ns = 0;
  std::uint64_t contact_ns = 0, dispatch_ns = 0;
};

class CollisionService {
 public:
  CollisionService(GpuThread& gpu, gpu::CollisionBackendDecision decision,
                   GpuPairFinder gpu_pairs = {});
  ~CollisionService();
  CollisionService(const CollisionService&) = delete;
  CollisionService& operator=(const CollisionService&) = delete;

  gpu::CollisionBackend backend() const { return decision_.backend; }
  CollisionSnapshot snapshot() const;

 private:
  friend class CollisionPairFinder;

  // Runs one detection on the GPU thread and waits for it; rethrows what the job threw.
  gpu::CollisionTimings detect_on_gpu(std::span<const glm::vec3> positions,
                                      std::span<const std::uint32_t> indices,
                                      std::span<const std::uint32_t> triangles,
                                      std::vector<deform::TrianglePair>& pairs);
  void count_fallback(const std::string& reason);
  void count_request(const deform::FeatureTimes& times, const gpu::CollisionTimings& gpu);

  GpuThread& gpu_;
  const gpu::CollisionBackendDecision decision_;
  std::string device_;
  GpuPairFinder gpu_pairs_;
  std::unique_ptr<gpu::CollisionDetector> detector_;  // touched only on the GPU thread
  std::atomic<std::uint64_t> requests_{0}, gpu_fallbacks_{0};
  std::atomic<std::uint64_t> detect_ns_{0}, fold_ns_{0}, protrude_ns_{0}, upload_ns_{0},
      readback_ns_{0}, contact_ns_{0}, dispatch_ns_{0};
  std::mutex logged_mutex_;
  std::set<std::string> logged_reasons_;
};

class CollisionPairFinder final : public sheet::PairSource {
 public:
  explicit CollisionPairFinder(CollisionService& service);
  CollisionPairFinder(const CollisionPairFinder&) = delete;
  CollisionPairFinder& operator=(const CollisionPairFinder&) = delete;

  const deform::DetectPairs& begin() override;
  void finish(const deform::FeatureReport& report) override;

 private:
  void detect(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
              std::span<const std::uint32_t> triangles, std::vector<deform::TrianglePair>& pairs);

  CollisionService& service_;
  deform::DetectPairs detect_;  // empty on the CPU backend
  deform::SelfIntersectionDetector cpu_;
  bool fell_back_ = false;  // this pose's GPU job threw: the CPU from then on
  gpu::CollisionTimings gpu_timings_;
};

}  // namespace sweepd::server
