#include "server/replies/contact_sheet_reply.h"

#include <vector>

#include "protocol/messages.h"

namespace sweepd::server {

void build_contact_sheet(flatbuffers::FlatBufferBuilder& builder, std::uint32_t model_id,
                         const sheet::SheetPicture& picture, std::uint64_t request_id) {
  namespace pb = sweepd::protocol;
  const std::vector<float> stretch(picture.worst_stretch.begin(), picture.worst_stretch.end());
  const auto reply = pb::CreateContactSheet(
      builder, model_id, static_cast<std::uint32_t>(picture.width),
      static_cast<std::uint32_t>(picture.height), builder.CreateVector(picture.png),
      builder.CreateVector(stretch), builder.CreateString(picture.renderer));
  pb::finish_message(builder, reply, request_id);
}

}  // namespace sweepd::server
