#include "client/clip_upload.h"

namespace sweepd::client {

namespace pb = sweepd::protocol;

const pb::ClipInfo& upload_clip(Connection& connection, std::string_view name, std::string_view bvh,
                                float length_scale, std::string_view joint_name_map) {
  flatbuffers::FlatBufferBuilder& builder = connection.builder();
  builder.Clear();
  const auto text = builder.CreateString(bvh.data(), bvh.size());
  const auto label = builder.CreateString(name.data(), name.size());
  const auto map = joint_name_map.empty()
                       ? 0
                       : builder.CreateString(joint_name_map.data(), joint_name_map.size());
  connection.send(
      pb::finish_message(builder, pb::CreateUploadClip(builder, label, text, length_scale, map)));
  return connection.expect<pb::ClipInfo>();
}

}  // namespace sweepd::client
