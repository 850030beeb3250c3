#include "server/handlers/mesh_request_handler.h"

#include <string>
#include <utility>

#include "server/handlers/reply_size.h"
#include "server/replies/mesh_reply.h"

namespace sweepd::server {

namespace pb = sweepd::protocol;

void handle_mesh_request(const pb::Message& message, RequestSession& session) {
  const std::uint64_t request_id = message.request_id();
  const ModelService& models = session.environment().models;
  const std::uint32_t model_id = message.body_as_MeshRequest()->model_id();
  const ModelHandle model = models.find(model_id);
  if (!model) {
    session.send_error(
        {pb::ErrorCode::UnknownModel, "mesh request: no model with id " + std::to_string(model_id) +
                                          " (" + held_models_clause(models) + ")"},
        request_id);
    return;
  }
  if (auto error = check_mesh_fits(model->bound.model, model_id,
                                   session.environment().config.max_frame_bytes)) {
    session.send_error(*error, request_id);
    return;
  }
  flatbuffers::FlatBufferBuilder builder = session.take_builder();
  build_mesh(builder, *model, request_id);
  session.send(std::move(builder));
}

}  // namespace sweepd::server
