// EditKeyEllipse: one rest key ellipse of a held model changed through ModelService (stored
// durably, which takes milliseconds: on a worker), answered with the model's new ModelInfo.
//
// Its working memory (the binding's copy, its runtime and self-check, the encoding: work_size.h)
// is reserved from the work budget on the I/O thread, sized by the held model's .sweepbind,
// before the work is queued, and held until it is done; an edit that does not fit is refused
// at once (ResourceExhausted naming the model, its vertices and binding bytes, the limit and
// what fits), changing nothing.
// read_key_ellipse_edit copies the edit from the frame on the I/O thread; run_key_ellipse_edit
// runs on a worker and gives the ModelChange: the model, or the ModelError's code with
// "edit key ellipse: " before its reason. log_edit_outcome logs key_ellipse_edited (its
// refusals are logged only as the Error reply).
#pragma once

#include <cstdint>

#include "deform/edits/rest_key_edit.h"
#include "protocol/sweepd_generated.h"
#include "server/handlers/model_change.h"
#include "server/handlers/request_session.h"
#include "server/models/model_service.h"

namespace sweepd::server {

struct KeyEllipseEditWork {
  std::uint32_t model_id = 0;
  deform::RestKeyEdit edit;
};
KeyEllipseEditWork read_key_ellipse_edit(const protocol::EditKeyEllipse& request);
ModelChange run_key_ellipse_edit(ModelService& models, const KeyEllipseEditWork& work);
void log_edit_outcome(std::uint64_t connection_id, const ModelChange& outcome);

void handle_edit_key_ellipse(const protocol::Message& message, RequestSession& session);

}  // namespace sweepd::server
