// The served model's rest skeleton, from its ModelInfo (protocol 1.1), so a client holds the
// served model whole (`sweepctl --server`: cli/served_model.h) without the model's file.
// Clients do not retarget clips with it: the server does (UploadClip, client/clip_upload.h).
//
//   rest_skeleton(info):            joints in model order (names, parents, rest T/R/S)
//
// Throws std::runtime_error when the server sent no rest skeleton (a 1.0 server).
#pragma once

#include "deform/model/skeleton.h"
#include "protocol/messages.h"

namespace sweepd::cli {

deform::Skeleton rest_skeleton(const protocol::ModelInfo& info);

}  // namespace sweepd::cli
