#include "server/handlers/edit_key_ellipse_handler.h"

#include <algorithm>
#include <memory>
#include <string>
#include <variant>

#include "console/text_format.h"
#include "server/handlers/work_size.h"
#include "server/log_event.h"

namespace sweepd::server {

namespace pb = sweepd::protocol;

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

void log_edit_outcome(std::uint64_t connection_id, const ModelChange& outcome) {
  if (const ModelHandle* model = std::get_if<ModelHandle>(&outcome)) {
    log_event("key_ellipse_edited", {{"connection", connection_id}, {"model", (*model)->id}});
  }
}

void handle_edit_key_ellipse(const pb::Message& message, RequestSession& session) {
  const KeyEllipseEditWork work = read_key_ellipse_edit(*message.body_as_EditKeyEllipse());
  ModelService& models = session.environment().models;
  // Sized by the model held now; one not held is refused by the worker (UnknownModel).
  std::shared_ptr<const WorkReservation> copy;
  if (const ModelHandle held = models.find(work.model_id)) {
    const std::uint64_t binding_bytes = held->file->size();
    auto reserved = session.environment().work_budget.reserve(
        session.connection_id(), key_ellipse_edit_work_bytes(binding_bytes));
    if (const WorkRefusal* refusal = std::get_if<WorkRefusal>(&reserved)) {
      session.send_error(
          work_refused("edit key ellipse of model '" + held->name + "' (" +
                           console::with_thousands(
                               static_cast<std::int64_t>(held->bound.model.vertex_count())) +
                           " vertices, " +
                           console::with_thousands(static_cast<std::int64_t>(binding_bytes)) +
                           " bytes of binding)",
                       *refusal, "an edit copies the whole binding"),
          message.request_id());
      return;
    }
    copy = std::get<std::shared_ptr<const WorkReservation>>(std::move(reserved));
  }
  answer_model_change(
      session, message.request_id(),
      [&models, work, copy = std::move(copy)]() { return run_key_ellipse_edit(models, work); },
      log_edit_outcome);
}

}  // namespace sweepd::server
