// ListModels: the held models and the store's model files (ModelList), built at once on the
// I/O thread.
#pragma once

#include "protocol/sweepd_generated.h"
#include "server/handlers/request_session.h"

namespace sweepd::server {

void handle_list_models(const protocol::Message& message, RequestSession& session);

}  // namespace sweepd::server
