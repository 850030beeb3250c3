// ClipStore: the motion clips sweepd holds for PoseFromClip and clip position maps (UploadClip,
// protocol 1.4), in memory only — a restart or another replica answers UnknownClip and the
// client uploads again (a clip is a few MB of text: cheaper to send again than to store).
//
// add(name, bvh, length_scale, joint_name_map): the clip named by clip_content_id of the three.
//   Text the store already holds is answered with the held clip, nothing parsed and nothing
//   counted. Otherwise the text is read (io::parse_bvh) and held, unless that would pass
//   max_clips clips or max_bytes BVH bytes in all (ClipLimit, saying which limit and how full),
//   or the text is not a usable BVH (ClipLoadFailed with the reader's line and reason; a clip
//   with no joints or no frames too), or the joint name map is not a JSON object of names
//   (InvalidArgument with the reason). Thread-safe; parses outside the lock.
// find(clip_id): the held clip, or nullptr. Thread-safe.
// HeldClip::retargeter(model): the clip retargeted onto a held model (motion::Retargeter on
//   the model's own mesh with the clip's joint name map, exactly as `sweepctl pose --bvh
//   [--bvh-map]` builds it, so a frame of it equals
//   that command's frame bit for bit), built on first use per model and kept while the model
//   is (an edited model is a new one). Thread-safe. Each retargeter keeps its own copy of the
//   frames: memory is about (1 + models posed with it) × the frames' floats per clip.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "motion/clip.h"
#include "motion/retarget.h"
#include "server/handlers/request_error.h"
#include "server/models/model_registry.h"

namespace sweepd::server {

class HeldClip {
 public:
  HeldClip(std::string id, std::string name, motion::Clip clip, motion::JointNameMap name_map,
           std::size_t bvh_bytes)
      : id_(std::move(id)),
        name_(std::move(name)),
        clip_(std::move(clip)),
        name_map_(std::move(name_map)),
        bytes_(bvh_bytes) {}

  const std::string& id() const { return id_; }
  const std::string& name() const { return name_; }
  const motion::Clip& clip() const { return clip_; }
  std::size_t bvh_bytes() const { return bytes_; }
  // Throws std::invalid_argument when the clip cannot drive the model (Retargeter's reasons).
  std::shared_ptr<const motion::Retargeter> retargeter(const ModelHandle& model) const;

 private:
  struct Retargeted {
    std::weak_ptr<const RegisteredModel> model;  // the key's model, while it is held
    std::shared_ptr<const motion::Retargeter> retargeter;
  };
  const std::string id_, name_;
  const motion::Clip clip_;
  const motion::JointNameMap name_map_;
  const std::size_t bytes_;
  mutable std::mutex mutex_;
  mutable std::map<const RegisteredModel*, Retargeted> retargeted_;
};

using ClipHandle = std::shared_ptr<const HeldClip>;

class ClipStore {
 public:
  ClipStore(std::uint32_t max_clips, std::uint64_t max_bytes)
      : max_clips_(max_clips), max_bytes_(max_bytes) {}

  std::variant<ClipHandle, RequestError> add(const std::string& name, std::string_view bvh,
                                             float length_scale,
                                             std::string_view joint_name_map = {});
  ClipHandle find(std::string_view clip_id) const;

 private:
  // Why one more clip of `bytes` does not fit, or "" (with mutex_ held).
  std::string room_problem(std::size_t bytes) const;

  const std::uint32_t max_clips_;
  const std::uint64_t max_bytes_;
  mutable std::mutex mutex_;
  std::map<std::string, ClipHandle, std::less<>> clips_;
  std::uint64_t bytes_ = 0;
};

}  // namespace sweepd::server
