#include "client/clip_upload.h"

namespace sweepd::client {

namespace pb = sweepd::protocol;

const pb::ClipInfo& upload_clip(Connection& connection, std::string_view name, std::string_view bvh,
                                float length_scale) {
  flatbuffers::FlatBufferBuilder& builder = connection.builder();
  builder.Clear();
  const auto text = builder.CreateString(bvh.data(), bvh.size());
  const auto label = builder.CreateString(name.data(), name.size());
  connection.send(
      pb::finish_message(builder, pb::CreateUploadClip(builder, label, text, length_scale)));
  return connection.expect<pb::ClipInfo>();
}

}  // namespace sweepd::client
