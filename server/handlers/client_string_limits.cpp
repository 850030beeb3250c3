#include "server/handlers/client_string_limits.h"

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace sweepd::server {

namespace {

namespace pb = protocol;

// Walks one request's strings, keeping the first that is over its bound. A field's label is
// made into a string only for a refusal: pose requests pass through here at stream rates.
class StringBounds {
 public:
  explicit StringBounds(std::uint64_t sequence) : sequence_(sequence) {}

  void check(std::string_view field, const flatbuffers::String* value, std::size_t limit) {
    if (value != nullptr) check(field, value->string_view(), limit);
  }

  void check_each(std::string_view field,
                  const flatbuffers::Vector<flatbuffers::Offset<flatbuffers::String>>* values,
                  std::size_t limit) {
    if (values == nullptr) return;
    for (flatbuffers::uoffset_t i = 0; i < values->size() && !refusal_; ++i) {
      if (values->Get(i)->size() > limit)
        check(std::string(field) + "[" + std::to_string(i) + "]", values->Get(i), limit);
    }
  }

  // A JSON text and the joint names inside it (object keys and string values). Text that is
  // not JSON is left to the request's own reader, which names what is wrong with it.
  void check_json(std::string_view field, const flatbuffers::String* value) {
    if (value == nullptr) return;
    check(field, value->string_view(), kMaxJsonBytes);
    if (refusal_) return;
    const nlohmann::json json = nlohmann::json::parse(value->string_view(), nullptr, false);
    if (!json.is_discarded()) check_json_names(field, json);
  }

  void check_clip_id(std::string_view field, const pb::ClipFrame* clip) {
    if (clip != nullptr) check(field, clip->clip_id(), kMaxContentIdBytes);
  }

  std::optional<RequestError> refusal() const { return refusal_; }

 private:
  void check(std::string_view field, std::string_view value, std::size_t limit) {
    if (refusal_ || value.size() <= limit) return;
    refusal_ = RequestError{pb::ErrorCode::InvalidArgument,
                            std::string(field) + " has " + std::to_string(value.size()) +
                                " bytes; the limit is " + std::to_string(limit) + " bytes",
                            sequence_};
  }

  // Iterative: 32 KiB of nested brackets would be thousands of frames deep on the I/O thread.
  void check_json_names(std::string_view field, const nlohmann::json& root) {
    const std::string label = std::string(field) + " name";
    std::vector<const nlohmann::json*> pending = {&root};
    while (!pending.empty() && !refusal_) {
      const nlohmann::json& json = *pending.back();
      pending.pop_back();
      if (json.is_string()) check(label, json.get_ref<const std::string&>(), kMaxNameBytes);
      if (json.is_array())
        for (const nlohmann::json& item : json) pending.push_back(&item);
      if (json.is_object()) {
        for (const auto& item : json.items()) {
          check(label, item.key(), kMaxNameBytes);
          pending.push_back(&item.value());
        }
      }
    }
  }

  std::uint64_t sequence_;
  std::optional<RequestError> refusal_;
};

// A pose request's sequence, which its refusal carries as every pose Error does; else 0.
std::uint64_t pose_sequence(const pb::Message& message) {
  const pb::Pose* pose = nullptr;
  if (const pb::PoseFromClip* request = message.body_as_PoseFromClip()) pose = request->pose();
  if (const pb::PositionMapRequest* request = message.body_as_PositionMapRequest())
    pose = request->pose();
  if (const pb::PoseByName* request = message.body_as_PoseByName()) pose = request->pose();
  return pose != nullptr ? pose->sequence() : 0;
}

}  // namespace

std::optional<RequestError> find_overlong_string(const pb::Message& message) {
  StringBounds bounds(pose_sequence(message));
  switch (message.body_type()) {
    case pb::Body::Hello:
      bounds.check("Hello.client_name", message.body_as_Hello()->client_name(), kMaxNameBytes);
      break;
    case pb::Body::LoadModel: {
      const pb::LoadModel* load = message.body_as_LoadModel();
      bounds.check("LoadModel.name", load->name(), kMaxPathBytes);
      bounds.check("LoadModel.content_id", load->content_id(), kMaxContentIdBytes);
      if (load->options() != nullptr)
        bounds.check_json("LoadModel.options.rig_map_json", load->options()->rig_map_json());
      break;
    }
    case pb::Body::EditKeyEllipse:
      bounds.check("EditKeyEllipse.sweep", message.body_as_EditKeyEllipse()->sweep(),
                   kMaxNameBytes);
      break;
    case pb::Body::UploadClip: {
      const pb::UploadClip* upload = message.body_as_UploadClip();
      bounds.check("UploadClip.name", upload->name(), kMaxNameBytes);
      bounds.check("UploadClip.animation", upload->animation(), kMaxNameBytes);
      bounds.check_json("UploadClip.joint_name_map", upload->joint_name_map());
      break;
    }
    case pb::Body::PoseFromClip:
      bounds.check_clip_id("PoseFromClip.clip.clip_id", message.body_as_PoseFromClip()->clip());
      break;
    case pb::Body::PositionMapRequest:
      bounds.check_clip_id("PositionMapRequest.clip.clip_id",
                           message.body_as_PositionMapRequest()->clip());
      break;
    case pb::Body::PoseByName:
      bounds.check_each("PoseByName.joint_names", message.body_as_PoseByName()->joint_names(),
                        kMaxNameBytes);
      break;
    case pb::Body::ContactSheetRequest: {
      const pb::ContactSheetRequest* request = message.body_as_ContactSheetRequest();
      bounds.check("ContactSheetRequest.clip_id", request->clip_id(), kMaxContentIdBytes);
      bounds.check_each("ContactSheetRequest.methods", request->methods(), kMaxNameBytes);
      bounds.check("ContactSheetRequest.focus", request->focus(), kMaxNameBytes);
      break;
    }
    case pb::Body::SubscribeStream:
      bounds.check("SubscribeStream.stream", message.body_as_SubscribeStream()->stream(),
                   kMaxNameBytes);
      break;
    default:
      break;
  }
  return bounds.refusal();
}

}  // namespace sweepd::server
