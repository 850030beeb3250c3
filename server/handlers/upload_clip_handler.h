// UploadClip (1.4): a BVH, a glTF animation or the range of motion read into the clip store
// on a worker (a BVH of megabytes takes milliseconds), with the connection's reading paused
// until its ClipInfo or error is queued. Played on the model the client names (1.12), what that
// leaves unmapped is said in the ClipInfo's warnings. While it is read, the upload's bytes and
// its decoded frames (work_size.h) are reserved from the server's work budget
// (ResourceExhausted, before any reading, when they do not fit now).
#pragma once

#include "protocol/sweepd_generated.h"
#include "server/handlers/request_session.h"

namespace sweepd::server {

void handle_upload_clip(const protocol::Message& message, RequestSession& session);

}  // namespace sweepd::server
