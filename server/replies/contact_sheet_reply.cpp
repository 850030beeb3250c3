#include "server/replies/contact_sheet_reply.h"

#include <vector>

#include "protocol/messages.h"

namespace sweepd::server {

void build_contact_sheet(flatbuffers::FlatBufferBuilder& builder, std::uint32_t model_id,
                         const sheet::SheetPicture& picture, std::uint64_t request_id) {
  namespace pb = sweepd::protocol;
  std::vector<float> change, shortest, longest;
  for (const sheet::EdgeRatios& cell : picture.edge_ratios) {
    change.push_back(static_cast<float>(cell.largest_change()));
    shortest.push_back(static_cast<float>(cell.shortest));
    longest.push_back(static_cast<float>(cell.longest));
  }
  const auto reply = pb::CreateContactSheet(
      builder, model_id, static_cast<std::uint32_t>(picture.width),
      static_cast<std::uint32_t>(picture.height), builder.CreateVector(picture.png),
      builder.CreateVector(change), builder.CreateString(picture.renderer),
      builder.CreateVector(shortest), builder.CreateVector(longest));
  pb::finish_message(builder, reply, request_id);
}

}  // namespace sweepd::server
