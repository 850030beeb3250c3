#include "server/handlers/load_model_handler.h"

#include <exception>
#include <memory>
#include <variant>

#include "console/text_format.h"
#include "server/handlers/work_size.h"
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

namespace {

std::string thousands(std::uint64_t n) {
  return console::with_thousands(static_cast<std::int64_t>(n));
}

// `bytes` of `budget` held for `client`, or ModelError{ResourceExhausted} naming `what` and
// saying what to ask instead (`smaller`).
std::shared_ptr<const void> hold_or_refuse(WorkBudget& budget, std::uint64_t client,
                                           std::uint64_t bytes, const std::string& what,
                                           const std::string& smaller = "upload a smaller model") {
  auto reserved = budget.reserve(client, bytes);
  if (const WorkRefusal* refusal = std::get_if<WorkRefusal>(&reserved))
    throw ModelError(pb::ErrorCode::ResourceExhausted,
                     work_refused(what, *refusal, smaller).message);
  return std::get<std::shared_ptr<const WorkReservation>>(std::move(reserved));
}

}  // namespace

ModelChange run_load_model(ModelService& models, const LoadModelWork& work, WorkBudget& budget,
                           std::uint64_t client) {
  ModelLoadRequest request;
  std::uint64_t file_bytes = 0;  // what the binding's reservation counts on
  request.hold_reading_memory = [&](std::uint64_t bytes) {
    file_bytes = bytes;
    return hold_or_refuse(budget, client, model_reading_work_bytes(bytes),
                          "reading model '" + work.name + "' (" + thousands(bytes) + " bytes)");
  };
  request.hold_binding_memory = [&](const deform::Model& model) {
    return hold_or_refuse(budget, client, model_binding_extra_bytes(model, file_bytes),
                          "binding model '" + model.name + "' (" + thousands(model.vertex_count()) +
                              " vertices, " + thousands(model.triangle_count()) + " triangles)");
  };
  request.hold_adoption_memory = [&](std::uint64_t bytes) {
    return hold_or_refuse(budget, client, model_adoption_work_bytes(bytes),
                          "adopting stored model " +
                              (work.content_id.empty() ? "'" + work.name + "'" : work.content_id) +
                              " (" + thousands(bytes) + " bytes of binding)",
                          "a stored model is read whole");
  };
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
  const pb::LoadModel& load = *message.body_as_LoadModel();
  const std::uint64_t upload_bytes = load.gltf() ? load.gltf()->size() : 0;
  WorkBudget& budget = session.environment().work_budget;
  const std::uint64_t client = session.connection_id();
  // The upload is copied off the frame, to wait for its turn: reserved before the copy.
  auto copy = budget.reserve(client, model_upload_work_bytes(upload_bytes));
  if (const WorkRefusal* refusal = std::get_if<WorkRefusal>(&copy)) {
    session.send_error(work_refused("model upload '" + (load.name() ? load.name()->str() : "") +
                                        "' (" + thousands(upload_bytes) + " bytes)",
                                    *refusal, "upload a smaller model"),
                       message.request_id());
    return;
  }
  auto work = std::make_shared<const LoadModelWork>(read_load_model(load));
  log_event("model_load_start",
            {{"connection", client}, {"name", work->name}, {"upload_bytes", work->gltf.size()}});
  answer_model_change(
      session, message.request_id(),
      [models = &session.environment().models, work, &budget, client,
       copy = std::get<std::shared_ptr<const WorkReservation>>(std::move(copy))]() {
        return run_load_model(*models, *work, budget, client);
      },
      log_load_outcome);
}

}  // namespace sweepd::server
