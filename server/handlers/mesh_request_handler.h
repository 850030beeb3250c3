// MeshRequest (1.1): a held model's rest mesh (Mesh), built at once on the I/O thread, or
// UnknownModel for an id no model has, or InvalidArgument when the mesh could not fit
// max_frame_bytes (reply_size.h; checked before it is built).
#pragma once

#include "protocol/sweepd_generated.h"
#include "server/handlers/request_session.h"

namespace sweepd::server {

void handle_mesh_request(const protocol::Message& message, RequestSession& session);

}  // namespace sweepd::server
