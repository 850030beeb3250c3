// The requests that read or change models, turned into work and replies through ModelService.
//
// answer_list_models / answer_mesh_request: built at once on the I/O thread (ModelList; Mesh,
//   or UnknownModel for an id no model has).
// A LoadModel or an EditKeyEllipse is read from its frame on the I/O thread (read_*: copies
// what the work needs, as the frame's storage is reused) and run on a worker (run_*: binding
// and storing take milliseconds to seconds). Either gives a ModelChange: the model as it now
// is, or the RequestError to answer (a load's ModelError code, Internal for any other
// failure; an edit's ModelError code with "edit key ellipse: " before its reason).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "deform/edits/rest_key_edit.h"
#include "protocol/sweepd_generated.h"
#include "server/handlers/request_error.h"
#include "server/models/model_service.h"

namespace sweepd::server {

using ModelChange = std::variant<ModelHandle, RequestError>;

void answer_list_models(const ModelService& models, std::uint64_t request_id,
                        flatbuffers::FlatBufferBuilder& builder);
std::optional<RequestError> answer_mesh_request(const ModelService& models,
                                                const protocol::MeshRequest& request,
                                                std::uint64_t request_id,
                                                flatbuffers::FlatBufferBuilder& builder);

// A LoadModel's fields (ModelLoadRequest's), its upload copied.
struct LoadModelWork {
  std::string content_id;
  std::string name;
  std::vector<std::uint8_t> gltf;
  std::string rig_map_json;
  int keys_per_link = 0;
  int orientation = 0;  // BindOptions.orientation: 0 linear, 1 smooth
};
LoadModelWork read_load_model(const protocol::LoadModel& load);
ModelChange run_load_model(ModelService& models, const LoadModelWork& work);

struct KeyEllipseEditWork {
  std::uint32_t model_id = 0;
  deform::RestKeyEdit edit;
};
KeyEllipseEditWork read_key_ellipse_edit(const protocol::EditKeyEllipse& request);
ModelChange run_key_ellipse_edit(ModelService& models, const KeyEllipseEditWork& work);

// The log events of a finished change, naming the connection that asked: a load's
// model_loaded (id, name, vertices, bind time) or model_load_failed (reason); an edit's
// key_ellipse_edited (its refusals are logged only as the Error reply).
using LogModelChange = void (*)(std::uint64_t connection_id, const ModelChange& outcome);
void log_load_outcome(std::uint64_t connection_id, const ModelChange& outcome);
void log_edit_outcome(std::uint64_t connection_id, const ModelChange& outcome);

}  // namespace sweepd::server
