// build_clip_info: the ClipInfo reply to an UploadClip (protocol 1.4) — the held clip's content
// id (what PoseFromClip names it by), its name, frame count, frame rate, joint count and the
// reader's warnings. Finishes `builder` as one frame carrying `request_id`.
#pragma once

#include <cstdint>

#include "protocol/sweepd_generated.h"
#include "server/models/clip_store.h"

namespace sweepd::server {

void build_clip_info(flatbuffers::FlatBufferBuilder& builder, const HeldClip& clip,
                     std::uint64_t request_id);

}  // namespace sweepd::server
