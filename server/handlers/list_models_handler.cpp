#include "server/handlers/list_models_handler.h"

#include <utility>

#include "server/replies/model_list_reply.h"

namespace sweepd::server {

namespace pb = sweepd::protocol;

void handle_list_models(const pb::Message& message, RequestSession& session) {
  const ModelService& models = session.environment().models;
  flatbuffers::FlatBufferBuilder builder = session.take_builder();
  build_model_list(builder, models.models(), models.directory_entries(), message.request_id());
  session.send(std::move(builder));
}

}  // namespace sweepd::server
