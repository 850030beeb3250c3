#include "server/replies/clip_info.h"

#include "protocol/messages.h"

namespace sweepd::server {

void build_clip_info(flatbuffers::FlatBufferBuilder& builder, const HeldClip& clip,
                     std::uint64_t request_id) {
  namespace pb = sweepd::protocol;
  const motion::Clip& motion = clip.clip();
  const auto info = pb::CreateClipInfo(
      builder, builder.CreateString(clip.id()), builder.CreateString(clip.name()),
      static_cast<std::uint32_t>(motion.frame_count), motion.frames_per_second(),
      static_cast<std::uint32_t>(motion.joints.size()),
      builder.CreateVectorOfStrings(motion.warnings));
  pb::finish_message(builder, info, request_id);
}

}  // namespace sweepd::server
