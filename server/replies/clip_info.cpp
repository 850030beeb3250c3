#include "server/replies/clip_info.h"

#include "protocol/messages.h"

namespace sweepd::server {

void build_clip_info(flatbuffers::FlatBufferBuilder& builder, const HeldClip& clip,
                     std::uint64_t request_id, std::span<const std::string> model_warnings) {
  namespace pb = sweepd::protocol;
  const motion::Clip& motion = clip.clip();
  std::vector<std::string> warnings = motion.warnings;
  warnings.insert(warnings.end(), model_warnings.begin(), model_warnings.end());
  const auto info = pb::CreateClipInfo(
      builder, builder.CreateString(clip.id()), builder.CreateString(clip.name()),
      static_cast<std::uint32_t>(motion.frame_count), motion.frames_per_second(),
      static_cast<std::uint32_t>(motion.joints.size()), builder.CreateVectorOfStrings(warnings));
  pb::finish_message(builder, info, request_id);
}

}  // namespace sweepd::server
