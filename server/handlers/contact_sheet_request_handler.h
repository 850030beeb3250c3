// ContactSheetRequest (1.11): `sweepctl sheet`'s grid of a held model and an uploaded clip,
// checked and copied on the I/O thread (read_contact_sheet_request), rendered by
// ContactSheetService on the GPU waiters' pool (its cells wait on the GPU thread) with the
// connection's reading paused, answered with the PNG (ContactSheet). A sheet whose PNG could
// pass max_frame_bytes is refused first (InvalidArgument, reply_size.h); its working memory
// (work_size.h) is reserved from the server's work budget until its reply is built
// (ResourceExhausted when it does not fit now); a render that throws is answered with
// error_code_of's code.
#pragma once

#include "protocol/sweepd_generated.h"
#include "server/handlers/request_session.h"

namespace sweepd::server {

void handle_contact_sheet_request(const protocol::Message& message, RequestSession& session);

}  // namespace sweepd::server
