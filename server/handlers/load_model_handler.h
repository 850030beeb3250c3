// LoadModel: a glTF upload (or a model the store or model directory holds, by content id or
// name) bound and registered through ModelService, answered with ModelInfo.
//
// Its working memory comes from the work budget (server/handlers/work_size.h) in three parts:
// the upload's copy, reserved on the I/O thread before the copy is taken (refused at once when
// it does not fit); on the worker, once the load's turn comes, its reading, then its binding
// once the model is read and its vertices and triangles are known (refused then). A model
// adopted from the store (another replica bound it) holds its reading instead, sized by its
// .sweepbind before it is read. Each refusal is ResourceExhausted naming the model, the bytes,
// the limit and what fits.
//
// read_load_model copies what the work needs from the frame on the I/O thread (its storage is
// reused by the next frame); run_load_model runs on a worker and gives the ModelChange: the
// model, or the RequestError to answer (the ModelError's code, Internal for any other
// failure); it holds the reading's and the binding's (or the adoption's) memory from `budget`
// for `client`.
// log_load_outcome: model_loaded (id, name, vertices, bind time) or model_load_failed (reason),
// naming the connection that asked.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "protocol/sweepd_generated.h"
#include "server/handlers/model_change.h"
#include "server/handlers/request_session.h"
#include "server/models/model_service.h"
#include "server/services/work_budget.h"

namespace sweepd::server {

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
ModelChange run_load_model(ModelService& models, const LoadModelWork& work, WorkBudget& budget,
                           std::uint64_t client);
void log_load_outcome(std::uint64_t connection_id, const ModelChange& outcome);

void handle_load_model(const protocol::Message& message, RequestSession& session);

}  // namespace sweepd::server
