// Reply size: the most bytes a pose request's reply (PosedVertices or PositionMap) can take,
// known at intake from the model and the request alone, so that a reply that could not fit the
// max_frame_bytes the server announces in Welcome is refused before any work (issue 49 item 2)
// instead of being computed and then cut or sent past the limit a client was promised.
//
// largest_reply_bytes(request): PosedVertices: the vertices in the requested format (Float32,
//   Float16, Meshopt at its codec's worst case; none when they go to shared memory) plus the
//   frame's fields; PositionMap: the EXR's texels uncompressed (OpenEXR stores a chunk raw when
//   compression would not shrink it) plus its chunk table, chunk headers and header.
// check_reply_fits(request, max_frame_bytes): the InvalidArgument naming the reply's size, the
//   limit and what to ask for instead, or nothing when it fits.
#pragma once

#include <cstdint>
#include <optional>

#include "server/handlers/pose_request.h"
#include "server/handlers/request_error.h"

namespace sweepd::server {

std::uint64_t largest_reply_bytes(const PoseRequest& request);

std::optional<RequestError> check_reply_fits(const PoseRequest& request,
                                             std::uint32_t max_frame_bytes);

}  // namespace sweepd::server
