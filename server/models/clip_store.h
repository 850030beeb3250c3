// ClipStore: the motion clips sweepd holds for PoseFromClip and clip position maps (UploadClip,
// protocol 1.4; glTF animations since 1.7), in memory only — a restart or another replica
// answers UnknownClip and the client uploads again (a clip is a few MB: cheaper to send again
// than to store).
//
// add(upload, models): an UploadClip as it came (ClipUpload: BVH text, or a glTF file's bytes
//   with the animation's name or index and whether it plays on the model's own joints, or (1.13)
//   a model's range of motion): checked (both kinds at once, a length_scale other than 1 on
//   glTF, or glTF options on BVH text are InvalidArgument) and handed to the BVH add, add_gltf
//   or add_range_of_motion. A range of motion needs model_id (else InvalidArgument), a model
//   `models` holds (else UnknownModel naming the held ones) and no clip fields besides (bvh,
//   gltf, animation, own_skeleton, joint_name_map, a length_scale other than 1: InvalidArgument
//   naming those given).
// add(name, bvh, length_scale, joint_name_map): the clip named by clip_content_id of the
//   three. Text the store already holds is answered with the held clip, nothing parsed and
//   nothing counted. Otherwise the text is read (io::parse_bvh) and held, unless that would pass
//   max_clips clips or max_bytes uploaded bytes in all (ClipLimit, saying which limit and how
//   full), or the text is not a usable BVH (ClipLoadFailed with the reader's line and reason; a
//   clip with no joints or no frames too), or the joint name map is not a JSON object of names
//   (InvalidArgument with the reason). Thread-safe; parses outside the lock.
// add_gltf(name, gltf, animation, own_skeleton, joint_name_map): the same for an animation of a
//   glTF file — or (1.8) of an FBX or COLLADA file, told apart by its first bytes
//   (gltf_clip_content_id; animation "" is "0"), read from the bytes alone by
//   io::load_model_clip (a glTF self-contained: the GLB chunk and data: URIs; any other URI
//   refused before a file is looked at, as for model uploads; assimp refuses every other file);
//   the file's bytes count against max_bytes.
//   ClipLoadFailed names the problem: bytes that are no glTF (truncated GLB, bad JSON), an
//   external URI, no animations, an unknown animation name or index (listing the file's), no
//   skin, an animation that drives none of the skin's joints.
// add_range_of_motion(model): (1.13) the model's range of motion, motion::range_of_motion of its
//   skeleton and bound rig map, named "range of motion" and held as an own_skeleton clip (played
//   joint for joint, motion::OwnSkeletonClip), under range_of_motion_clip_id of the model's
//   content id. A held one is answered at once; a new one is built (a few milliseconds) and
//   counts the bytes of its keys against max_bytes (a key a frame for each joint it turns:
//   28 KB a joint), as an upload counts its text. ClipLoadFailed when the rig map does not fit.
// find(clip_id): the held clip, or nullptr. Thread-safe.
// HeldClip::player(model): the clip played on a held model — motion::Retargeter on the model's
//   own mesh with the clip's joint name map, exactly as `sweepctl pose --bvh [--bvh-map]` and
//   `--clip-from` build it, or for an own_skeleton glTF clip motion::OwnSkeletonClip on the
//   model's skeleton, as `sweepctl pose MODEL.glb --clip` builds it — so a frame of it equals
//   that command's frame bit for bit. Built on first use per model and kept while the model
//   is (an edited model is a new one). Thread-safe. The players share the held clip's frames:
//   memory is the clip's floats once, plus a few per-joint tables per model.
// warnings_on_model(clip, models, model_id): (1.12, UploadClip.model_id) what playing the clip
//   on that held model leaves undone, for ClipInfo.warnings — its player's warnings (built now,
//   and kept for the frames asked for next), each "on model 'NAME': ..." (the clip joints that
//   drive no model joint, the model joints left without motion); or one warning saying that no
//   model has that id (naming the held ones) or why the clip cannot play on it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "motion/clip.h"
#include "motion/clip_poses.h"
#include "motion/joint_name_map.h"
#include "server/handlers/request_error.h"
#include "server/models/model_lookup.h"
#include "server/models/model_registry.h"

namespace sweepd::server {

class HeldClip {
 public:
  HeldClip(std::string id, std::string name, motion::Clip clip, motion::JointNameMap name_map,
           bool own_skeleton, std::size_t upload_bytes)
      : id_(std::move(id)),
        name_(std::move(name)),
        clip_(std::make_shared<const motion::Clip>(std::move(clip))),
        name_map_(std::move(name_map)),
        own_skeleton_(own_skeleton),
        bytes_(upload_bytes) {}

  const std::string& id() const { return id_; }
  const std::string& name() const { return name_; }
  const motion::Clip& clip() const { return *clip_; }
  std::size_t upload_bytes() const { return bytes_; }
  // Throws std::invalid_argument when the clip cannot drive the model (the Retargeter's or
  // OwnSkeletonClip's reasons).
  std::shared_ptr<const motion::ClipPoses> player(const ModelHandle& model) const;

 private:
  struct Played {
    std::weak_ptr<const RegisteredModel> model;  // the key's model, while it is held
    std::shared_ptr<const motion::ClipPoses> player;
  };
  const std::string id_, name_;
  const std::shared_ptr<const motion::Clip> clip_;  // shared by the players, never copied
  const motion::JointNameMap name_map_;
  const bool own_skeleton_;
  const std::size_t bytes_;
  mutable std::mutex mutex_;
  mutable std::map<const RegisteredModel*, Played> players_;
};

using ClipHandle = std::shared_ptr<const HeldClip>;

// An UploadClip's fields, owned (the frame's storage is reused once the worker has them);
// of_message copies them out of a received message.
struct ClipUpload {
  static ClipUpload of_message(const protocol::UploadClip& upload);

  std::string name;
  std::string bvh;
  std::vector<std::uint8_t> gltf;  // (1.7) instead of bvh
  std::string animation;           // with gltf
  bool own_skeleton = false;       // with gltf
  float length_scale = 1.0f;
  std::string joint_name_map;
  std::optional<std::uint32_t> model_id;  // (1.12) the model whose warnings ClipInfo carries
  bool range_of_motion = false;           // (1.13) model_id's range of motion, made here
};

std::vector<std::string> warnings_on_model(const HeldClip& clip, const ModelLookup& models,
                                           std::uint32_t model_id);

class ClipStore {
 public:
  ClipStore(std::uint32_t max_clips, std::uint64_t max_bytes)
      : max_clips_(max_clips), max_bytes_(max_bytes) {}

  std::variant<ClipHandle, RequestError> add(const ClipUpload& upload, const ModelLookup& models);
  std::variant<ClipHandle, RequestError> add(const std::string& name, std::string_view bvh,
                                             float length_scale,
                                             std::string_view joint_name_map = {});
  std::variant<ClipHandle, RequestError> add_gltf(const std::string& name,
                                                  std::span<const std::uint8_t> gltf,
                                                  const std::string& animation, bool own_skeleton,
                                                  std::string_view joint_name_map = {});
  std::variant<ClipHandle, RequestError> add_range_of_motion(const RegisteredModel& model);
  ClipHandle find(std::string_view clip_id) const;

 private:
  // The clip `id` of `bytes` uploaded bytes: the held one, or `read()` (which throws with the
  // reader's reason: ClipLoadFailed) held with `name_map` (InvalidArgument when it is not a
  // JSON object of names) if it fits.
  std::variant<ClipHandle, RequestError> admit(const std::string& id, const std::string& name,
                                               std::size_t bytes, std::string_view name_map,
                                               bool own_skeleton,
                                               const std::function<motion::Clip()>& read);
  // Why one more clip of `bytes` does not fit, or "" (with mutex_ held).
  std::string room_problem(std::size_t bytes) const;

  const std::uint32_t max_clips_;
  const std::uint64_t max_bytes_;
  mutable std::mutex mutex_;
  std::map<std::string, ClipHandle, std::less<>> clips_;
  std::uint64_t bytes_ = 0;
};

}  // namespace sweepd::server
