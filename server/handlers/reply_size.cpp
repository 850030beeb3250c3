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

// A PNG of width x height RGBA pixels as stb_image_write makes it, at worst: its filtered rows
// (a filter byte each) deflated with fixed Huffman codes, 9 bits a byte at worst, in one IDAT;
// then signature, IHDR, IDAT and IEND chunks, zlib's header and checksum.
std::uint64_t largest_png_bytes(std::uint64_t width, std::uint64_t height) {
  const std::uint64_t filtered = height * (4 * width + 1);
  return filtered + filtered / 8 + 1 + 64;
}

std::string over_the_limit(std::uint64_t bytes, std::uint32_t max_frame_bytes) {
  return "its reply can reach " + console::with_thousands(static_cast<std::int64_t>(bytes)) +
         " bytes, over this server's max_frame_bytes " +
         console::with_thousands(static_cast<std::int64_t>(max_frame_bytes)) +
         " (announced in Welcome); ";
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
  std::string message =
      "pose " + std::to_string(request.sequence) + ": " + over_the_limit(bytes, max_frame_bytes);
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

std::uint64_t largest_sheet_reply_bytes(const sheet::SheetOptions& options) {
  const std::uint64_t columns = options.methods.size(), rows = options.frames.size();
  // The renderer's name (GL_RENDERER) is a line of text: 1 KiB holds it.
  return largest_png_bytes(options.cell_width * columns, options.cell_height * rows) +
         4 * rows * columns + 1024 + kFrameFieldsBytes;
}

std::optional<RequestError> check_sheet_fits(const sheet::SheetOptions& options,
                                             std::uint32_t max_frame_bytes) {
  const std::uint64_t bytes = largest_sheet_reply_bytes(options);
  if (bytes <= max_frame_bytes) return std::nullopt;
  // The largest cell of the same aspect that fits, if it is not below the smallest cell.
  sheet::SheetOptions smaller = options;
  const double scale = std::sqrt(static_cast<double>(max_frame_bytes) / static_cast<double>(bytes));
  smaller.cell_width = static_cast<int>(options.cell_width * scale);
  smaller.cell_height = static_cast<int>(options.cell_height * scale);
  while (largest_sheet_reply_bytes(smaller) > max_frame_bytes && smaller.cell_width > 0 &&
         smaller.cell_height > 0) {
    smaller.cell_width = smaller.cell_width * 99 / 100;
    smaller.cell_height = smaller.cell_height * 99 / 100;
  }
  const bool cell_fits = smaller.cell_width >= sheet::ContactSheet::kSmallestCell &&
                         smaller.cell_height >= sheet::ContactSheet::kSmallestCell;
  return RequestError{
      protocol::ErrorCode::InvalidArgument,
      "contact sheet: " + over_the_limit(bytes, max_frame_bytes) + "ask for " +
          (cell_fits ? "smaller cells (" + std::to_string(smaller.cell_width) + " x " +
                           std::to_string(smaller.cell_height) + " fits), "
                     : std::string()) +
          "fewer frames or methods, or a server started with a larger --max-frame-bytes"};
}

std::uint64_t mesh_reply_bytes(const deform::Model& model) {
  const std::uint64_t n = model.vertex_count();
  // Each vector: its length and up to 8 bytes of alignment besides its elements.
  return 4 * model.indices.size() + 8 * model.uvs.size() + 12 * n + 2 * deform::kInfluences * n +
         4 * deform::kInfluences * n + 5 * 12 + kFrameFieldsBytes;
}

std::optional<RequestError> check_mesh_fits(const deform::Model& model, std::uint32_t model_id,
                                            std::uint32_t max_frame_bytes) {
  const std::uint64_t bytes = mesh_reply_bytes(model);
  if (bytes <= max_frame_bytes) return std::nullopt;
  return RequestError{protocol::ErrorCode::InvalidArgument,
                      "mesh request: model " + std::to_string(model_id) + ": " +
                          over_the_limit(bytes, max_frame_bytes) +
                          "a mesh is sent whole, so ask a server started with a larger "
                          "--max-frame-bytes, or read the model's own file for its mesh"};
}

}  // namespace sweepd::server
