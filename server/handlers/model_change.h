// ModelChange: what a model load or key-ellipse edit gives — the model as it now is, or the
// RequestError to answer. answer_model_change(session, request_id, change, log_outcome): runs
// `change` on a worker (binding and storing take milliseconds to seconds) with the
// connection's reading paused, then on the I/O thread logs the outcome (`log_outcome`, naming
// the connection) and answers ModelInfo or the error, so replies stay in request order.
#pragma once

#include <cstdint>
#include <functional>
#include <variant>

#include "server/handlers/request_error.h"
#include "server/handlers/request_session.h"
#include "server/models/model_registry.h"

namespace sweepd::server {

using ModelChange = std::variant<ModelHandle, RequestError>;
using LogModelChange = void (*)(std::uint64_t connection_id, const ModelChange& outcome);

void answer_model_change(RequestSession& session, std::uint64_t request_id,
                         std::function<ModelChange()> change, LogModelChange log_outcome);

}  // namespace sweepd::server
