#include "server/handlers/work_size.h"

#include <algorithm>
#include <utility>
#include <variant>

#include "console/text_format.h"
#include "server/handlers/reply_size.h"

namespace sweepd::server {
namespace {

constexpr std::uint64_t kDeformedVertexBytes = 2 * 3 * 4;  // float32 positions and normals

std::uint64_t map_texel_work_bytes(const PositionMapParams& map) {
  const bool normals = has_layer(map.layers, protocol::MapLayers::Normal);
  const std::uint64_t render_targets = 16 + 16 + 4;
  const std::uint64_t read_back = 12 + (normals ? 12 : 0) + 4;
  const std::uint64_t gutter = 1 + 3 * 4;
  const std::uint64_t half_normals = normals && map.half_normals ? 6 : 0;
  return render_targets + read_back + gutter + half_normals;
}

}  // namespace

std::uint64_t pose_work_bytes(const PoseRequest& request) {
  const std::uint64_t reply = largest_reply_bytes(request);
  const std::uint64_t deformed = kDeformedVertexBytes * request.model->bound.model.vertex_count();
  if (const std::optional<PositionMapParams>& map = request.position_map) {
    const std::uint64_t texels = std::uint64_t{map->width} * map->height;
    return texels * map_texel_work_bytes(*map) + 4 * reply + deformed;
  }
  if (request.format == protocol::PositionFormat::Float32) return reply;
  return reply + deformed;
}

std::uint64_t sheet_work_bytes(const sheet::SheetOptions& options) {
  const std::uint64_t cell_pixels =
      static_cast<std::uint64_t>(options.cell_width) * options.cell_height;
  const std::uint64_t cell = cell_pixels * (4 * 4 + 4 * 4 + 4 + 4);
  return 8 * options.pixel_count() + 5 * largest_sheet_reply_bytes(options) + cell;
}

std::uint64_t clip_upload_work_bytes(std::uint64_t upload_bytes) { return 4 * upload_bytes; }

std::uint64_t model_upload_work_bytes(std::uint64_t upload_bytes) { return upload_bytes; }

std::uint64_t model_reading_work_bytes(std::uint64_t file_bytes) { return 5 * file_bytes; }

std::uint64_t model_binding_work_bytes(const deform::Model& model) {
  return std::uint64_t{900} * model.vertex_count() + std::uint64_t{256} * model.triangle_count();
}

std::uint64_t model_adoption_work_bytes(std::uint64_t binding_bytes) { return 10 * binding_bytes; }

std::uint64_t key_ellipse_edit_work_bytes(std::uint64_t binding_bytes) {
  return 12 * binding_bytes;
}

std::uint64_t model_binding_extra_bytes(const deform::Model& model, std::uint64_t file_bytes) {
  const std::uint64_t binding = model_binding_work_bytes(model);
  const std::uint64_t reading = model_reading_work_bytes(file_bytes);
  return binding > reading ? binding - reading : 0;
}

std::string describe(const WorkRefusal& refusal) {
  const auto thousands = [](std::uint64_t n) {
    return console::with_thousands(static_cast<std::int64_t>(n));
  };
  const std::uint64_t fitting = refusal.limit - std::min(refusal.limit, refusal.in_use);
  return "needs " + thousands(refusal.bytes) + " bytes of working memory, over " +
         (refusal.over_share
              ? "this client's share of the server's work budget (--work-budget-client-bytes " +
                    thousands(refusal.limit) + ", " + thousands(refusal.in_use) +
                    " held by this client's requests now"
              : "what the server's work budget has free now (--work-budget-bytes " +
                    thousands(refusal.limit) + ", " + thousands(refusal.in_use) +
                    " held by all clients") +
         ": " + thousands(fitting) + " fit)";
}

RequestError work_refused(const std::string& what, const WorkRefusal& refusal,
                          const std::string& smaller) {
  return RequestError{protocol::ErrorCode::ResourceExhausted,
                      what + ": " + describe(refusal) + "; " + smaller +
                          ", or retry when this server's other work has finished"};
}

std::optional<RequestError> reserve_pose_work(PoseRequest& request, WorkBudget& budget,
                                              std::uint64_t client) {
  auto reserved = budget.reserve(client, pose_work_bytes(request));
  if (auto* work = std::get_if<std::shared_ptr<const WorkReservation>>(&reserved)) {
    request.work = std::move(*work);
    return std::nullopt;
  }
  const std::string smaller =
      request.position_map ? "ask for a smaller map or fewer layers"
      : request.format == protocol::PositionFormat::Float32
          ? "ask for fewer at once"
          : "ask for Float32 vertices (deformed straight into the reply) or fewer at once";
  const std::string pose = "pose " + std::to_string(request.sequence);
  RequestError error = work_refused(request.position_map ? "position map of " + pose : pose,
                                    std::get<WorkRefusal>(reserved), smaller);
  error.sequence = request.sequence;
  return error;
}

}  // namespace sweepd::server
