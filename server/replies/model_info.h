// build_model_info: a ModelInfo reply for a registered model — joint names and parents in
// model order (what Pose.rotations follow), vertex/triangle counts, UVs, a summary of the
// binding (rig convention, sweeps, key ellipses, swept and skinned vertex counts), and the rest
// skeleton with the mesh's floor, so a client holds the served model whole
// (cli/served_rest_skeleton.h), and (1.14) the binding's self-check: each region where the sweep
// is still worse than skinning (RegisteredModel::self_check). Finishes `builder` as one frame
// carrying `request_id`.
#pragma once

#include <cstdint>

#include "protocol/sweepd_generated.h"
#include "server/models/model_registry.h"

namespace sweepd::server {

void build_model_info(flatbuffers::FlatBufferBuilder& builder, const RegisteredModel& model,
                      std::uint64_t request_id);

}  // namespace sweepd::server
