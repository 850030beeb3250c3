#include "server/services/position_map_service.h"

#include <optional>

#include "gpu/gpu_worker.h"
#include "gpu/position_map_renderer.h"
#include "io/exr/exr_write.h"

namespace sweepd::server {
namespace {

constexpr int kGutterPixels = 4;

std::optional<io::ExrCompression> exr_compression(protocol::ExrCompression compression) {
  switch (compression) {
    case protocol::ExrCompression::Uncompressed:
      return io::ExrCompression::kNone;
    case protocol::ExrCompression::Zips:
      return io::ExrCompression::kZips;
    case protocol::ExrCompression::Zip:
      return io::ExrCompression::kZip;
    case protocol::ExrCompression::Piz:
      return io::ExrCompression::kPiz;
    default:
      return std::nullopt;  // Rle, or newer than this server
  }
}

}  // namespace

bool has_layer(protocol::MapLayers layers, protocol::MapLayers layer) {
  return (static_cast<unsigned>(layers) & static_cast<unsigned>(layer)) != 0;
}

std::string check_position_map_request(const protocol::PositionMapRequest& request,
                                       const deform::Model& model) {
  const std::string side =
      std::to_string(request.width()) + " x " + std::to_string(request.height());
  if (request.width() < 1 || request.height() < 1 || request.width() > kMaxPositionMapSide ||
      request.height() > kMaxPositionMapSide) {
    return "position map of " + side + " texels: each side must be 1 to " +
           std::to_string(kMaxPositionMapSide);
  }
  if (!model.has_uvs()) return "model '" + model.name + "' has no UVs to map positions into";
  if (!exr_compression(request.compression())) {
    return std::string("EXR compression ") +
           protocol::EnumNameExrCompression(request.compression()) +
           " is not offered; use Uncompressed, Zips, Zip or Piz";
  }
  if (!has_layer(request.layers(), protocol::MapLayers::Position)) {
    return "a position map needs its Position layer";
  }
  return "";
}

PositionMapService::PositionMapService(bool enabled, GpuThread& gpu)
    : enabled_(enabled), gpu_(gpu) {}

PositionMapService::~PositionMapService() {
  // GL objects go with the context, on the worker's thread, before the worker ends.
  if (renderer_) worker().submit([this](gpu::Context&) { renderer_.reset(); }).get();
}

gpu::Worker& PositionMapService::worker() {
  if (!enabled_) {
    throw PositionMapUnavailable(
        "renders (position maps, contact sheets) are switched off on this server (--position-maps "
        "0)");
  }
  gpu::Worker* worker = gpu_.start();
  if (worker == nullptr) {
    throw PositionMapUnavailable("no GPU context for renders (position maps, contact sheets): " +
                                 gpu_.failure());
  }
  return *worker;
}

void PositionMapService::render(const PositionMapJob& job, std::vector<std::uint8_t>& exr) {
  const auto width = static_cast<int>(job.width);
  const auto height = static_cast<int>(job.height);
  const std::size_t texels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  const bool normals = has_layer(job.layers, protocol::MapLayers::Normal) && !job.normals.empty();
  const bool coverage = has_layer(job.layers, protocol::MapLayers::Coverage);
  std::vector<float> p(texels * 3), n(normals ? texels * 3 : 0), a(coverage ? texels : 0);

  // renderer_ belongs to the worker's thread and context: made by the first job, used only
  // inside jobs (which the worker runs one at a time). The job's references outlive it: we
  // wait for its result here.
  worker()
      .submit([&](gpu::Context& context) {
        if (!renderer_) renderer_ = std::make_unique<gpu::PositionMapRenderer>(context);
        const deform::Model& model = *job.model;
        renderer_->render({model.uvs, job.positions,
                           normals ? job.normals : std::span<const glm::vec3>(), model.indices},
                          {.width = width,
                           .height = height,
                           .gutter_pixels = kGutterPixels,
                           .view = std::nullopt},
                          {p, n, a});
      })
      .get();

  io::ExrOptions options;
  options.compression = *exr_compression(job.compression);
  options.half_normals = job.half_normals;
  options.model = job.model->name;
  options.frame = static_cast<int>(job.frame);
  options.pose_hash = job.pose_hash;
  io::encode_exr({width, height, p, n, a}, options, exr);
}

}  // namespace sweepd::server
