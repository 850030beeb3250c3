// PositionMapService: the answer to PositionMapRequest — a posed mesh rasterised in UV space
// (gpu::PositionMapRenderer) on the server's one GPU worker thread (gpu::Worker, shared by
// all connections), then encoded as an OpenEXR file in memory (io::encode_exr).
//
// The GPU worker (GpuThread, shared with collision detection) starts on the first request
// unless it already runs (EGL: a real GPU, or Mesa llvmpipe); when no EGL context can be made,
// that and every later request throws PositionMapUnavailable with the driver's reason.
// render() may be called from any thread; it waits for the GPU job.
//
// Input (PositionMapJob): the model (UVs and triangles), its posed positions and normals
// (vertex_count each), width × height (1..kMaxPositionMapSide), the layers and compression.
// Output: `exr` resized to the file's bytes: channels P.X/Y/Z, N.X/Y/Z when asked for, A
// (coverage) when asked for; every channel float32; a 4-texel gutter around UV islands.
// Throws std::invalid_argument (a model without UVs, a size out of range, an unsupported
// compression) naming the problem.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "deform/model/model.h"
#include "protocol/sweepd_generated.h"
#include "server/services/gpu_thread.h"

namespace sweepd::gpu {
class PositionMapRenderer;
}  // namespace sweepd::gpu

namespace sweepd::server {

inline constexpr std::uint32_t kMaxPositionMapSide = 4096;

// Whether a request's layer flags include `layer`.
bool has_layer(protocol::MapLayers layers, protocol::MapLayers layer);

class PositionMapUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct PositionMapJob {
  const deform::Model* model = nullptr;
  std::span<const glm::vec3> positions;
  std::span<const glm::vec3> normals;
  std::uint32_t width = 0, height = 0;
  protocol::MapLayers layers = protocol::MapLayers::Position;
  protocol::ExrCompression compression = protocol::ExrCompression::Zip;
  bool half_normals = false;  // N channels as float16
  std::uint64_t frame = 0;      // written into the EXR header ("frame")
  std::uint64_t pose_hash = 0;  // and "poseHash" (deform/model/pose_hash.h)
};

// What is wrong with a request for `model`, or "" when it can be rendered.
std::string check_position_map_request(const protocol::PositionMapRequest& request,
                                       const deform::Model& model);

class PositionMapService {
 public:
  // `gpu` must outlive this service.
  PositionMapService(bool enabled, GpuThread& gpu);
  ~PositionMapService();

  bool enabled() const { return enabled_; }
  void render(const PositionMapJob& job, std::vector<std::uint8_t>& exr);
  // The GPU worker for renders (position maps, contact sheets: ContactSheetService), started on
  // first use; throws PositionMapUnavailable when renders are off or EGL gives no context.
  gpu::Worker& worker();

 private:
  bool enabled_;
  GpuThread& gpu_;
  std::unique_ptr<gpu::PositionMapRenderer> renderer_;  // touched only on the worker's thread
};

}  // namespace sweepd::server
