#include "server/models/model_service.h"

#include <chrono>

#include "deform/binding/bind.h"
#include "deform/rig/rig_map.h"
#include "mannequin/mannequin.h"
#include "server/log_event.h"

namespace sweepd::server {

ModelService::ModelService(const ServerConfig& config)
    : config_(config),
      registry_(
          config.store_dir, config.model_dir,
          {.max_models = config.max_models, .max_model_vertices = config.max_model_vertices}) {}

void ModelService::restore() {
  for (const std::string& problem : registry_.restore()) {
    log_event("restore_problem", {{"reason", problem}});
  }
  for (const ModelHandle& model : registry_.models()) {
    log_event("model_restored", {{"model", model->id},
                                 {"name", model->name},
                                 {"vertices", model->bound.model.vertex_count()}});
  }
}

void ModelService::add_default_model() {
  if (!config_.model_dir.empty() || registry_.find(std::string_view("mannequin"))) return;
  const auto started = std::chrono::steady_clock::now();
  deform::Model model = mannequin::make_mannequin({.target_vertices = config_.mannequin_vertices});
  const deform::RigMap rig = deform::detect_rig_map(model.skeleton);
  deform::BoundModel bound = deform::bind(model, rig);
  const auto bind_time = std::chrono::duration_cast<std::chrono::nanoseconds>(
      std::chrono::steady_clock::now() - started);
  const ModelHandle added =
      registry_.add("mannequin", std::move(bound), static_cast<std::uint64_t>(bind_time.count()));
  log_event("model_loaded", {{"model", added->id},
                             {"name", added->name},
                             {"vertices", added->bound.model.vertex_count()},
                             {"bind_time_ns", added->bind_time_ns}});
}

ModelHandle ModelService::edit_key_ellipse(std::uint32_t model_id,
                                           const deform::RestKeyEdit& edit) {
  const ModelHandle model = registry_.find(model_id);
  if (!model)
    throw ModelError(protocol::ErrorCode::UnknownModel,
                     "no model with id " + std::to_string(model_id));
  deform::BoundModel bound = model->bound;
  if (const std::string problem = deform::apply_rest_key_edit(bound, edit); !problem.empty())
    throw ModelError(protocol::ErrorCode::InvalidArgument, problem);
  return registry_.replace(model_id, std::move(bound));
}

}  // namespace sweepd::server
