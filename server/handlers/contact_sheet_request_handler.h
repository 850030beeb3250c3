// ContactSheetRequest (1.11): `sweepctl sheet`'s grid of a held model and an uploaded clip,
// checked and copied on the I/O thread (read_contact_sheet_request), rendered by
// ContactSheetService on the GPU waiters' pool (its cells wait on the GPU thread) with the
// connection's reading paused, answered with the PNG (ContactSheet). Its pixels are taken from
// the server's buffer budget while it is drawn (ResourceExhausted when there is no room); a
// render that throws is answered with error_code_of's code.
#pragma once

#include "protocol/sweepd_generated.h"
#include "server/handlers/request_session.h"

namespace sweepd::server {

void handle_contact_sheet_request(const protocol::Message& message, RequestSession& session);

}  // namespace sweepd::server
