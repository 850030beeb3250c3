// build_clip_info: the ClipInfo reply to an UploadClip (protocol 1.4) — the held clip's content
// id (what PoseFromClip names it by), its name, frame count, frame rate, joint count and the
// reader's warnings, then `model_warnings` (1.12: what playing it on UploadClip.model_id's model
// leaves undone, warnings_on_model). Finishes `builder` as one frame carrying `request_id`.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "protocol/sweepd_generated.h"
#include "server/models/clip_store.h"

namespace sweepd::server {

void build_clip_info(flatbuffers::FlatBufferBuilder& builder, const HeldClip& clip,
                     std::uint64_t request_id, std::span<const std::string> model_warnings = {});

}  // namespace sweepd::server
