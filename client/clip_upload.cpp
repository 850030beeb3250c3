#include "client/clip_upload.h"

namespace sweepd::client {

namespace pb = sweepd::protocol;

namespace {

flatbuffers::Optional<std::uint32_t> optional_id(std::optional<std::uint32_t> id) {
  return id ? flatbuffers::Optional<std::uint32_t>(*id) : flatbuffers::nullopt;
}

}  // namespace

const pb::ClipInfo& upload_clip(Connection& connection, std::string_view name, std::string_view bvh,
                                float length_scale, std::string_view joint_name_map,
                                std::optional<std::uint32_t> model_id) {
  flatbuffers::FlatBufferBuilder& builder = connection.builder();
  builder.Clear();
  const auto text = builder.CreateString(bvh.data(), bvh.size());
  const auto label = builder.CreateString(name.data(), name.size());
  const auto map = joint_name_map.empty()
                       ? 0
                       : builder.CreateString(joint_name_map.data(), joint_name_map.size());
  connection.send(
      pb::finish_message(builder, pb::CreateUploadClip(builder, label, text, length_scale, map, 0,
                                                       0, false, optional_id(model_id))));
  return connection.expect<pb::ClipInfo>();
}

const pb::ClipInfo& upload_gltf_clip(Connection& connection, std::string_view name,
                                     std::span<const std::uint8_t> gltf, std::string_view animation,
                                     bool own_skeleton, std::string_view joint_name_map,
                                     std::optional<std::uint32_t> model_id) {
  flatbuffers::FlatBufferBuilder& builder = connection.builder();
  builder.Clear();
  const auto bytes = builder.CreateVector(gltf.data(), gltf.size());
  const auto label = builder.CreateString(name.data(), name.size());
  const auto chosen = builder.CreateString(animation.data(), animation.size());
  const auto map = joint_name_map.empty()
                       ? 0
                       : builder.CreateString(joint_name_map.data(), joint_name_map.size());
  connection.send(
      pb::finish_message(builder, pb::CreateUploadClip(builder, label, 0, 1.0f, map, bytes, chosen,
                                                       own_skeleton, optional_id(model_id))));
  return connection.expect<pb::ClipInfo>();
}

const pb::ClipInfo& upload_range_of_motion(Connection& connection, std::uint32_t model_id) {
  flatbuffers::FlatBufferBuilder& builder = connection.builder();
  builder.Clear();
  connection.send(pb::finish_message(
      builder, pb::CreateUploadClip(builder, 0, 0, 1.0f, 0, 0, 0, false, model_id, true)));
  return connection.expect<pb::ClipInfo>();
}

}  // namespace sweepd::client
