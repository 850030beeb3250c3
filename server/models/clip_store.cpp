#include "server/models/clip_store.h"

#include <cmath>
#include <stdexcept>

#include "io/bvh_load.h"
#include "io/joint_name_map_json.h"
#include "io/load_error.h"
#include "server/models/content_id.h"

namespace sweepd::server {

std::shared_ptr<const motion::Retargeter> HeldClip::retargeter(const ModelHandle& model) const {
  {
    const std::lock_guard lock(mutex_);
    std::erase_if(retargeted_, [](const auto& entry) { return entry.second.model.expired(); });
    if (auto found = retargeted_.find(model.get()); found != retargeted_.end())
      return found->second.retargeter;
  }
  // Built outside the lock (milliseconds: rig maps of both skeletons, the model's floor); two
  // first requests at once build it twice and keep the first.
  auto built = std::make_shared<const motion::Retargeter>(clip_, model->bound.model, name_map_);
  const std::lock_guard lock(mutex_);
  return retargeted_.try_emplace(model.get(), Retargeted{model, std::move(built)})
      .first->second.retargeter;
}

std::variant<ClipHandle, RequestError> ClipStore::add(const std::string& name, std::string_view bvh,
                                                      float length_scale,
                                                      std::string_view joint_name_map) {
  const std::string id = clip_content_id(bvh, length_scale, joint_name_map);
  {
    const std::lock_guard lock(mutex_);
    if (auto held = clips_.find(id); held != clips_.end()) return held->second;
    if (std::string problem = room_problem(bvh.size()); !problem.empty())
      return RequestError{protocol::ErrorCode::ClipLimit, std::move(problem)};
  }
  if (!std::isfinite(length_scale) || length_scale <= 0.0f)
    return RequestError{protocol::ErrorCode::InvalidArgument, "clip '" + name + "': length_scale " +
                                                                  std::to_string(length_scale) +
                                                                  " must be finite and > 0"};
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
    clip = io::parse_bvh(bvh, name, {.length_scale = length_scale});
    if (clip.joints.empty() || clip.frame_count == 0)
      throw std::invalid_argument(name + ": the clip has no " +
                                  (clip.joints.empty() ? "joints" : "frames"));
  } catch (const std::exception& error) {
    return RequestError{protocol::ErrorCode::ClipLoadFailed, error.what()};
  }
  auto held =
      std::make_shared<const HeldClip>(id, name, std::move(clip), std::move(name_map), bvh.size());
  const std::lock_guard lock(mutex_);
  if (auto again = clips_.find(id); again != clips_.end()) return again->second;  // raced
  if (std::string problem = room_problem(bvh.size()); !problem.empty())
    return RequestError{protocol::ErrorCode::ClipLimit, std::move(problem)};
  bytes_ += bvh.size();
  clips_.emplace(id, held);
  return held;
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
           " BVH bytes does not fit: " + std::to_string(bytes_) + " of the server's " +
           std::to_string(max_bytes_) + " clip bytes are held (--max-clip-bytes)";
  return {};
}

}  // namespace sweepd::server
