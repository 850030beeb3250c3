#include "server/handlers/load_model_handler.h"

#include <exception>
#include <memory>

#include "server/log_event.h"

namespace sweepd::server {

namespace pb = sweepd::protocol;

LoadModelWork read_load_model(const pb::LoadModel& load) {
  LoadModelWork work;
  work.content_id = load.content_id() ? load.content_id()->str() : "";
  work.name = load.name() ? load.name()->str() : "";
  if (load.gltf()) work.gltf.assign(load.gltf()->begin(), load.gltf()->end());
  if (load.options() && load.options()->rig_map_json()) {
    work.rig_map_json = load.options()->rig_map_json()->str();
  }
  if (load.options()) {
    work.keys_per_link = load.options()->keys_per_link();
    work.orientation = load.options()->orientation();
  }
  return work;
}

ModelChange run_load_model(ModelService& models, const LoadModelWork& work) {
  ModelLoadRequest request;
  request.content_id = work.content_id;
  request.name = work.name;
  request.gltf = work.gltf;
  request.rig_map_json = work.rig_map_json;
  request.keys_per_link = work.keys_per_link;
  request.orientation = work.orientation;
  try {
    return models.load(request);
  } catch (const ModelError& error) {
    return RequestError{error.code(), error.what()};
  } catch (const std::exception& error) {
    return RequestError{pb::ErrorCode::Internal, error.what()};
  }
}

void log_load_outcome(std::uint64_t connection_id, const ModelChange& outcome) {
  if (const ModelHandle* model = std::get_if<ModelHandle>(&outcome)) {
    log_event("model_loaded", {{"connection", connection_id},
                               {"model", (*model)->id},
                               {"content_id", (*model)->content_id},
                               {"name", (*model)->name},
                               {"vertices", (*model)->bound.model.vertex_count()},
                               {"bind_time_ns", (*model)->bind_time_ns}});
  } else {
    log_event("model_load_failed",
              {{"connection", connection_id}, {"reason", std::get<RequestError>(outcome).message}});
  }
}

void handle_load_model(const pb::Message& message, RequestSession& session) {
  auto work = std::make_shared<const LoadModelWork>(read_load_model(*message.body_as_LoadModel()));
  log_event("model_load_start", {{"connection", session.connection_id()},
                                 {"name", work->name},
                                 {"upload_bytes", work->gltf.size()}});
  answer_model_change(
      session, message.request_id(),
      [models = &session.environment().models, work]() { return run_load_model(*models, *work); },
      log_load_outcome);
}

}  // namespace sweepd::server
