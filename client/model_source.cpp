#include "client/model_source.h"

namespace sweepd::client {

namespace pb = sweepd::protocol;

std::string model_name_of_file(const std::filesystem::path& file) { return file.stem().string(); }

ModelSource::ModelSource(std::string name, std::vector<std::uint8_t> glb, std::string rig_map_json,
                         std::uint8_t orientation)
    : name_(std::move(name)),
      rig_map_json_(std::move(rig_map_json)),
      glb_(std::move(glb)),
      orientation_(orientation) {}

const pb::ModelInfo& ModelSource::request(Connection& connection, const std::string& content_id,
                                          bool with_bytes) {
  flatbuffers::FlatBufferBuilder& builder = connection.builder();
  builder.Clear();
  const auto rig_map = rig_map_json_.empty() ? 0 : builder.CreateString(rig_map_json_);
  const auto options = rig_map_json_.empty() && orientation_ == 0
                           ? 0
                           : pb::CreateBindOptions(builder, rig_map, 0, orientation_);
  const auto bytes = with_bytes && !glb_.empty() ? builder.CreateVector(glb_) : 0;
  const auto id = content_id.empty() ? 0 : builder.CreateString(content_id);
  connection.send(pb::finish_message(
      builder, pb::CreateLoadModel(builder, builder.CreateString(name_), bytes, options, id)));
  return connection.expect<pb::ModelInfo>();
}

const pb::ModelInfo& ModelSource::load(Connection& connection) {
  std::string known;
  {
    std::lock_guard lock(mutex_);
    known = content_id_;
  }
  if (!known.empty()) {
    try {
      return request(connection, known, /*with_bytes=*/false);
    } catch (const ServerError& error) {
      if (error.code() != pb::ErrorCode::UnknownModel) throw;
    }
  }
  const pb::ModelInfo& info = request(connection, "", /*with_bytes=*/true);
  std::lock_guard lock(mutex_);
  if (!glb_.empty()) ++uploads_;
  remember(info);
  return info;
}

void ModelSource::remember(const pb::ModelInfo& info) {
  if (content_id_.empty() && info.content_id()) content_id_ = info.content_id()->str();
}

int ModelSource::uploads() const {
  std::lock_guard lock(mutex_);
  return uploads_;
}

}  // namespace sweepd::client
