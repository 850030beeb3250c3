// Reply size: the most bytes a request's reply (PosedVertices, PositionMap, ContactSheet, Mesh)
// can take, known at intake from the model and the request alone, so that a reply that could not
// fit the
// max_frame_bytes the server announces in Welcome is refused before any work (issue 49 item 2)
// instead of being computed and then cut or sent past the limit a client was promised.
//
// largest_reply_bytes(request): PosedVertices: the vertices in the requested format (Float32,
//   Float16, Meshopt at its codec's worst case; none when they go to shared memory) plus the
//   frame's fields; PositionMap: the EXR's texels uncompressed (OpenEXR stores a chunk raw when
//   compression would not shrink it) plus its chunk table, chunk headers and header.
// check_reply_fits(request, max_frame_bytes): the InvalidArgument naming the reply's size, the
//   limit and what to ask for instead, or nothing when it fits.
// largest_sheet_reply_bytes(options): a ContactSheet: the PNG as stb_image_write can make it at
//   worst (filtered rows under fixed-Huffman deflate: 9 bits a byte) plus the cells' worst
//   stretches and the frame's fields. check_sheet_fits: its InvalidArgument, suggesting the
//   largest cell of the same aspect that fits, or fewer frames or methods.
// mesh_reply_bytes(model): a Mesh: indices, UVs, rest positions, skin joints and weights (the
//   reply is exactly these; there is no smaller form). check_mesh_fits: its InvalidArgument.
// The other replies are small or bounded by an input that passed the same limit (ModelInfo:
// names and ranges of an uploaded model; ModelList: --max-models and a directory's names; Stats:
// --max-connections rows).
#pragma once

#include <cstdint>
#include <optional>

#include "server/handlers/pose_request.h"
#include "server/handlers/request_error.h"
#include "server/services/contact_sheet_service.h"

namespace sweepd::server {

std::uint64_t largest_reply_bytes(const PoseRequest& request);

std::optional<RequestError> check_reply_fits(const PoseRequest& request,
                                             std::uint32_t max_frame_bytes);

std::uint64_t largest_sheet_reply_bytes(const sheet::SheetOptions& options);

std::optional<RequestError> check_sheet_fits(const sheet::SheetOptions& options,
                                             std::uint32_t max_frame_bytes);

std::uint64_t mesh_reply_bytes(const deform::Model& model);

std::optional<RequestError> check_mesh_fits(const deform::Model& model, std::uint32_t model_id,
                                            std::uint32_t max_frame_bytes);

}  // namespace sweepd::server
