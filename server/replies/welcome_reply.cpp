#include "server/replies/welcome_reply.h"

#include <string>
#include <vector>

#include "protocol/messages.h"

namespace sweepd::server {

void build_welcome(flatbuffers::FlatBufferBuilder& builder, const ServerConfig& config,
                   bool position_maps, bool shared_memory, std::uint64_t connection_id,
                   std::uint64_t request_id) {
  namespace pb = sweepd::protocol;
  std::vector<std::string> capabilities = {
      "sweep",        "lbs",     "dqs",        "folding",     "protrusion", "volume",
      "bulge",        "float16", "normals",    "latest_wins", "upload",     "clips",
      "pose_by_name", "meshopt", "gltf_clips", "contact",     "fbx_clips"};
  if (position_maps) {
    capabilities.push_back("position_map");
    capabilities.push_back("contact_sheet");  // 1.11: the same renders
  }
  if (shared_memory) capabilities.push_back("shared_memory");
  const auto welcome =
      pb::CreateWelcome(builder, pb::kProtocolVersionMajor, pb::kProtocolVersionMinor,
                        builder.CreateString("sweepd"), builder.CreateVectorOfStrings(capabilities),
                        config.max_frame_bytes, config.max_poses_in_flight, connection_id);
  pb::finish_message(builder, welcome, request_id);
}

}  // namespace sweepd::server
