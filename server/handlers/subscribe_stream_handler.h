// SubscribeStream (1.15): the connection receives the posed meshes of a stream the server
// receives (a VMC stream, named by its model: server/services/vmc/vmc_receivers.h), a PosedVertices per frame,
// deformed as the request's pose says (method, features, output), latest wins: the connection
// must have said LatestWins in Hello, so that a client slower than the stream gets its newest
// frame, never a backlog. Answered StreamSubscribed at once; refused with NotAvailable (no
// stream received: no --vmc-listen), InvalidArgument (no stream of that name, InOrder delivery,
// no pose, a pose carrying rotations, a root translation or a method, feature or output the
// server refuses) or UnknownModel (the stream's model is not held: load it first). Each frame's
// pose is checked as a client's is (rotations normalised); a frame that fails is answered with
// that pose's Error. The subscription ends with its connection, and once the connection drains
// (Bye, shutdown).
#pragma once

#include "protocol/sweepd_generated.h"
#include "server/handlers/request_session.h"

namespace sweepd::server {

void handle_subscribe_stream(const protocol::Message& message, RequestSession& session);

}  // namespace sweepd::server
