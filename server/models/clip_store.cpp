#include "server/models/clip_store.h"

#include <cmath>
#include <stdexcept>

#include "io/bvh/bvh_load.h"
#include "io/files/load_error.h"
#include "io/json/joint_name_map_json.h"
#include "io/model_clip_load.h"
#include "motion/name_list.h"
#include "motion/own_skeleton_clip.h"
#include "motion/range_of_motion.h"
#include "motion/retarget.h"
#include "server/models/content_id.h"

namespace sweepd::server {

std::shared_ptr<const motion::ClipPoses> HeldClip::player(const ModelHandle& model) const {
  {
    const std::lock_guard lock(mutex_);
    std::erase_if(players_, [](const auto& entry) { return entry.second.model.expired(); });
    if (auto found = players_.find(model.get()); found != players_.end())
      return found->second.player;
  }
  // Built outside the lock (rig maps of both skeletons, the model's floor, and foot planting's
  // pass over every clip frame: 40 ms for cmu_01_03's 4,511 frames on the 72k mannequin); two
  // first requests at once build it twice and keep the first.
  std::shared_ptr<const motion::ClipPoses> built;
  if (own_skeleton_)
    built = std::make_shared<const motion::OwnSkeletonClip>(clip_, model->bound.model.skeleton);
  else
    built = std::make_shared<const motion::Retargeter>(clip_, model->bound.model, name_map_);
  const std::lock_guard lock(mutex_);
  return players_.try_emplace(model.get(), Played{model, std::move(built)}).first->second.player;
}

ClipUpload ClipUpload::of_message(const protocol::UploadClip& upload) {
  const auto text = [](const flatbuffers::String* s) { return s ? s->str() : std::string(); };
  ClipUpload copied;
  copied.name = text(upload.name());
  copied.bvh = text(upload.bvh());
  if (upload.gltf()) copied.gltf.assign(upload.gltf()->begin(), upload.gltf()->end());
  copied.animation = text(upload.animation());
  copied.own_skeleton = upload.own_skeleton();
  copied.length_scale = upload.length_scale();
  copied.joint_name_map = text(upload.joint_name_map());
  if (const flatbuffers::Optional<std::uint32_t> model = upload.model_id(); model.has_value())
    copied.model_id = *model;
  copied.range_of_motion = upload.range_of_motion();
  return copied;
}

std::vector<std::string> warnings_on_model(const HeldClip& clip, const ModelLookup& models,
                                           std::uint32_t model_id) {
  const ModelHandle model = models.find(model_id);
  if (!model)
    return {"no model with id " + std::to_string(model_id) + " to play it on (" +
            held_models_clause(models) + "): its joints were not matched"};
  const std::string on = "on model '" + model->name + "': ";
  try {
    std::vector<std::string> warnings;
    for (const std::string& warning : clip.player(model)->warnings())
      warnings.push_back(on + warning);
    return warnings;
  } catch (const std::invalid_argument& e) {
    return {on + "it cannot play there: " + e.what()};
  }
}

std::variant<ClipHandle, RequestError> ClipStore::add(const ClipUpload& upload,
                                                      const ModelLookup& models) {
  const auto invalid = [&](const std::string& reason) {
    return RequestError{protocol::ErrorCode::InvalidArgument,
                        "clip '" + upload.name + "': " + reason};
  };
  if (upload.range_of_motion) {
    const auto refused = [](protocol::ErrorCode code, const std::string& reason) {
      return RequestError{code, "range of motion: " + reason};
    };
    std::vector<std::string> given;
    if (!upload.bvh.empty()) given.push_back("bvh");
    if (!upload.gltf.empty()) given.push_back("gltf");
    if (!upload.animation.empty()) given.push_back("animation");
    if (upload.own_skeleton) given.push_back("own_skeleton");
    if (!upload.joint_name_map.empty()) given.push_back("joint_name_map");
    if (upload.length_scale != 1.0f) given.push_back("length_scale");
    if (!given.empty())
      return refused(protocol::ErrorCode::InvalidArgument,
                     "the server builds it from the model, but the upload also carries " +
                         motion::name_list(given) + ": send range_of_motion with model_id alone");
    if (!upload.model_id)
      return refused(protocol::ErrorCode::InvalidArgument,
                     "model_id is required: the clip is built from that model's skeleton and rig "
                     "map");
    const ModelHandle model = models.find(*upload.model_id);
    if (!model)
      return refused(protocol::ErrorCode::UnknownModel,
                     "no model with id " + std::to_string(*upload.model_id) + " (" +
                         held_models_clause(models) + ")");
    return add_range_of_motion(*model);
  }
  if (upload.gltf.empty()) {
    if (!upload.animation.empty() || upload.own_skeleton)
      return invalid("animation and own_skeleton choose a glTF animation: send the file's bytes");
    return add(upload.name, upload.bvh, upload.length_scale, upload.joint_name_map);
  }
  if (!upload.bvh.empty()) return invalid("both BVH text and glTF bytes: send one clip");
  if (upload.length_scale != 1.0f)
    return invalid("length_scale " + std::to_string(upload.length_scale) +
                   " applies to BVH text; a glTF clip is in metres (send 1)");
  return add_gltf(upload.name, upload.gltf, upload.animation, upload.own_skeleton,
                  upload.joint_name_map);
}

std::variant<ClipHandle, RequestError> ClipStore::add(const std::string& name, std::string_view bvh,
                                                      float length_scale,
                                                      std::string_view joint_name_map) {
  if (!std::isfinite(length_scale) || length_scale <= 0.0f)
    return RequestError{protocol::ErrorCode::InvalidArgument, "clip '" + name + "': length_scale " +
                                                                  std::to_string(length_scale) +
                                                                  " must be finite and > 0"};
  return admit(clip_content_id(bvh, length_scale, joint_name_map), name, bvh.size(), joint_name_map,
               false, [&] {
                 motion::Clip clip = io::parse_bvh(bvh, name, {.length_scale = length_scale});
                 if (clip.joints.empty() || clip.frame_count == 0)
                   throw std::invalid_argument(name + ": the clip has no " +
                                               (clip.joints.empty() ? "joints" : "frames"));
                 return clip;
               });
}

std::variant<ClipHandle, RequestError> ClipStore::add_gltf(const std::string& name,
                                                           std::span<const std::uint8_t> gltf,
                                                           const std::string& animation,
                                                           bool own_skeleton,
                                                           std::string_view joint_name_map) {
  const std::string chosen = animation.empty() ? "0" : animation;
  return admit(gltf_clip_content_id(gltf, chosen, own_skeleton, joint_name_map), name, gltf.size(),
               joint_name_map, own_skeleton,
               [&] { return io::load_model_clip(gltf, name, chosen); });
}

std::variant<ClipHandle, RequestError> ClipStore::admit(const std::string& id,
                                                        const std::string& name, std::size_t bytes,
                                                        std::string_view joint_name_map,
                                                        bool own_skeleton,
                                                        const std::function<motion::Clip()>& read) {
  {
    const std::lock_guard lock(mutex_);
    if (auto held = clips_.find(id); held != clips_.end()) return held->second;
    if (std::string problem = room_problem(bytes); !problem.empty())
      return RequestError{protocol::ErrorCode::ClipLimit, std::move(problem)};
  }
  motion::JointNameMap name_map;
  try {
    if (!joint_name_map.empty())
      name_map =
          io::parse_joint_name_map_json(joint_name_map, "clip '" + name + "' joint_name_map");
  } catch (const std::exception& error) {
    return RequestError{protocol::ErrorCode::InvalidArgument, error.what()};
  }
  motion::Clip clip;
  try {
    clip = read();
  } catch (const std::exception& error) {
    return RequestError{protocol::ErrorCode::ClipLoadFailed, error.what()};
  }
  auto held = std::make_shared<const HeldClip>(id, name, std::move(clip), std::move(name_map),
                                               own_skeleton, bytes);
  const std::lock_guard lock(mutex_);
  if (auto again = clips_.find(id); again != clips_.end()) return again->second;  // raced
  if (std::string problem = room_problem(bytes); !problem.empty())
    return RequestError{protocol::ErrorCode::ClipLimit, std::move(problem)};
  bytes_ += bytes;
  clips_.emplace(id, held);
  return held;
}

std::variant<ClipHandle, RequestError> ClipStore::add_range_of_motion(
    const RegisteredModel& model) {
  const std::string id = range_of_motion_clip_id(model.content_id);
  if (ClipHandle held = find(id)) return held;
  // Built before admit, which wants the bytes held (two first requests at once build it twice
  // and keep the first).
  motion::Clip clip;
  try {
    clip = motion::range_of_motion(model.bound.model.skeleton, model.bound.rig).clip;
  } catch (const std::exception& error) {
    return RequestError{protocol::ErrorCode::ClipLoadFailed,
                        "range of motion of model '" + model.name + "': " + error.what()};
  }
  std::size_t bytes = 0;
  for (const motion::KeyframeTrack& track : clip.tracks)
    bytes += (track.times.size() + track.values.size()) * sizeof(float);
  return admit(id, motion::kRomClipName, bytes, {}, true, [&] { return std::move(clip); });
}

ClipHandle ClipStore::find(std::string_view clip_id) const {
  const std::lock_guard lock(mutex_);
  const auto held = clips_.find(clip_id);
  return held == clips_.end() ? nullptr : held->second;
}

std::string ClipStore::room_problem(std::size_t bytes) const {
  if (clips_.size() >= max_clips_)
    return "the server holds its maximum of " + std::to_string(max_clips_) + " clips (--max-clips)";
  if (bytes_ + bytes > max_bytes_)
    return "a clip of " + std::to_string(bytes) +
           " uploaded bytes does not fit: " + std::to_string(bytes_) + " of the server's " +
           std::to_string(max_bytes_) + " clip bytes are held (--max-clip-bytes)";
  return {};
}

}  // namespace sweepd::server
