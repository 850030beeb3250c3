// build_model_list: the ModelList reply to ListModels — one summary per loaded model (id, name,
// vertex and joint counts), by id, then one per model file in the model directory not loaded
// yet (its file name; id and counts 0). Finishes `builder` as one frame carrying `request_id`.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "protocol/sweepd_generated.h"
#include "server/models/model_registry.h"

namespace sweepd::server {

void build_model_list(flatbuffers::FlatBufferBuilder& builder, std::span<const ModelHandle> models,
                      std::span<const std::string> directory_entries, std::uint64_t request_id);

}  // namespace sweepd::server
