#include "server/handlers/model_requests.h"

#include <algorithm>
#include <exception>

#include "server/log_event.h"
#include "server/replies/mesh_reply.h"
#include "server/replies/model_list_reply.h"

namespace sweepd::server {

namespace pb = sweepd::protocol;

void answer_list_models(const ModelService& models, std::uint64_t request_id,
                        flatbuffers::FlatBufferBuilder& builder) {
  build_model_list(builder, models.models(), models.directory_entries(), request_id);
}

std::optional<RequestError> answer_mesh_request(const ModelService& models,
                                                const pb::MeshRequest& request,
                                                std::uint64_t request_id,
                                                flatbuffers::FlatBufferBuilder& builder) {
  const ModelHandle model = models.find(request.model_id());
  if (!model) {
    return RequestError{pb::ErrorCode::UnknownModel, "mesh request: no model with id " +
                                                         std::to_string(request.model_id()) + " (" +
                                                         held_models_clause(models) + ")"};
  }
  build_mesh(builder, *model, request_id);
  return std::nullopt;
}

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

KeyEllipseEditWork read_key_ellipse_edit(const pb::EditKeyEllipse& request) {
  KeyEllipseEditWork work;
  work.model_id = request.model_id();
  deform::RestKeyEdit& edit = work.edit;
  edit.sweep = request.sweep() ? request.sweep()->str() : "";
  edit.key = static_cast<int>(std::min<std::uint32_t>(request.key_index(), 1u << 30));
  if (const pb::Vec3* offset = request.centre_offset())
    edit.centre_offset = {offset->x(), offset->y(), offset->z()};
  edit.a = request.half_axis_a();
  edit.b = request.half_axis_b();
  edit.twist_radians = request.twist_radians();
  return work;
}

ModelChange run_key_ellipse_edit(ModelService& models, const KeyEllipseEditWork& work) {
  try {
    return models.edit_key_ellipse(work.model_id, work.edit);
  } catch (const ModelError& error) {
    return RequestError{error.code(), std::string("edit key ellipse: ") + error.what()};
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

void log_edit_outcome(std::uint64_t connection_id, const ModelChange& outcome) {
  if (const ModelHandle* model = std::get_if<ModelHandle>(&outcome)) {
    log_event("key_ellipse_edited", {{"connection", connection_id}, {"model", (*model)->id}});
  }
}

}  // namespace sweepd::server
