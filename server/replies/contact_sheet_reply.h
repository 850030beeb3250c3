// build_contact_sheet: the ContactSheet reply to a ContactSheetRequest (protocol 1.11) — the
// picture's size, its PNG bytes, each cell's worst edge stretch (row by row) and the renderer.
// Finishes `builder` as one frame carrying `request_id`.
#pragma once

#include <cstdint>

#include "protocol/sweepd_generated.h"
#include "server/services/contact_sheet_service.h"

namespace sweepd::server {

void build_contact_sheet(flatbuffers::FlatBufferBuilder& builder, std::uint32_t model_id,
                         const sheet::SheetPicture& picture, std::uint64_t request_id);

}  // namespace sweepd::server
