#include "server/handlers/reply_size.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "console/text_format.h"
#include "protocol/meshopt_vertices.h"
#include "server/services/position_map_service.h"

namespace sweepd::server {
namespace {

// The envelope, the request's fields echoed, timings and alignment padding: a few hundred bytes.
constexpr std::uint64_t kFrameFieldsBytes = 1024;
// An EXR header (channels, our attributes: frame, pose hash, a model name of at most
// kMaxNameBytes) stays below this.
constexpr std::uint64_t kExrHeaderBytes = 8 * 1024;

std::uint64_t texel_bytes(const PositionMapParams& map) {
  std::uint64_t bytes = 3 * 4;  // Position: float32
  if (has_layer(map.layers, protocol::MapLayers::Normal)) bytes += 3 * (map.half_normals ? 2 : 4);
  if (has_layer(map.layers, protocol::MapLayers::Coverage)) bytes += 4;
  return bytes;
}

std::uint64_t map_bytes(const PositionMapParams& map, std::uint64_t width, std::uint64_t height) {
  // Texels, then per scan line at most one chunk: its offset in the table and its header.
  return width * height * texel_bytes(map) + 16 * height + kExrHeaderBytes + kFrameFieldsBytes;
}

}  // namespace

std::uint64_t largest_reply_bytes(const PoseRequest& request) {
  if (request.position_map)
    return map_bytes(*request.position_map, request.position_map->width,
                     request.position_map->height);
  if (request.shared_offset) return kFrameFieldsBytes;  // the vertices go to shared memory
  const std::uint64_t n = request.model->bound.model.vertex_count();
  const std::uint64_t streams = request.normals ? 2 : 1;
  switch (request.format) {
    case protocol::PositionFormat::Float16:
      return streams * n * 3 * 2 + kFrameFieldsBytes;
    case protocol::PositionFormat::Meshopt:
      return protocol::meshopt_bytes_bound(n, request.normals) + kFrameFieldsBytes;
    default:
      return streams * n * 3 * 4 + kFrameFieldsBytes;
  }
}

std::optional<RequestError> check_reply_fits(const PoseRequest& request,
                                             std::uint32_t max_frame_bytes) {
  const std::uint64_t bytes = largest_reply_bytes(request);
  if (bytes <= max_frame_bytes) return std::nullopt;
  std::string message = "pose " + std::to_string(request.sequence) + ": its reply can reach " +
                        console::with_thousands(static_cast<std::int64_t>(bytes)) +
                        " bytes, over this server's max_frame_bytes " +
                        console::with_thousands(static_cast<std::int64_t>(max_frame_bytes)) +
                        " (announced in Welcome); ";
  if (const std::optional<PositionMapParams>& map = request.position_map) {
    // The largest map of the same aspect and layers that fits (none when the headers alone
    // do not).
    double scale = std::sqrt(static_cast<double>(max_frame_bytes) / static_cast<double>(bytes));
    std::uint64_t width = 0, height = 0;
    for (; scale > 0.0; scale *= 0.99) {
      width = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(map->width * scale));
      height = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(map->height * scale));
      if (map_bytes(*map, width, height) <= max_frame_bytes || (width == 1 && height == 1)) break;
    }
    const bool some_fits = map_bytes(*map, width, height) <= max_frame_bytes;
    message += (some_fits ? "ask for a smaller map (" + std::to_string(width) + " x " +
                                std::to_string(height) + " fits), fewer layers"
                          : std::string("ask for fewer layers")) +
               (has_layer(map->layers, protocol::MapLayers::Normal) && !map->half_normals
                    ? std::string(" or PositionMapRequest.half_normals")
                    : std::string()) +
               ", or a server started with a larger --max-frame-bytes";
  } else {
    message += std::string("ask for ") +
               (request.format == protocol::PositionFormat::Float32 ? "Float16 or " : "") +
               (request.format != protocol::PositionFormat::Meshopt ? "Meshopt vertices, " : "") +
               (request.normals ? "no normals, " : "") +
               "the vertices in shared memory (over the Unix socket: MapSharedMemory, then "
               "Pose.into_shared_memory), or a "
               "server started with a larger --max-frame-bytes";
  }
  return RequestError{protocol::ErrorCode::InvalidArgument, std::move(message), request.sequence,
                      request.model->id};
}

}  // namespace sweepd::server
