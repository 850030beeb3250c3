// build_mesh: the Mesh reply to a MeshRequest (protocol 1.1) — the model's rest mesh in its
// vertex order: triangle indices (#I), UVs (2 × #V floats), positions (3 × #V floats), skin
// joints and weights (kInfluences × #V each). Finishes `builder` as one frame carrying
// `request_id`.
#pragma once

#include <cstdint>

#include "protocol/sweepd_generated.h"
#include "server/models/model_registry.h"

namespace sweepd::server {

void build_mesh(flatbuffers::FlatBufferBuilder& builder, const RegisteredModel& registered,
                std::uint64_t request_id);

}  // namespace sweepd::server
