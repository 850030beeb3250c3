// RemotePosedModel: what `sweepctl --server HOST:PORT pose|positionmap|metrics` share — the
// posing commands' model and pose source, with the deformation done by a sweepd daemon.
//
// MODEL is a local .glb/.gltf/.fbx/.dae (uploaded with LoadModel, named by its file's base name,
// client/model_source.h: model_name_of_file; always with its bytes, which a server holding them
// answers at once without binding — by name alone it would take another file of that base
// name — and "already loaded" when the server listed them under that name) or, when no such file
// exists, the name of a model on the server (e.g. "mannequin"). The model's mesh comes back with
// MeshRequest, so results are written as the local commands write them. A clip — a BVH (with its
// --bvh-map), a
// --clip-from glTF animation, or (protocol 1.7) --clip's animation of MODEL's own file — is
// uploaded once (UploadClip) and each frame is asked for by number: the server plays it, as
// `sweepctl pose --bvh|--clip-from|--clip` does locally (`metrics` plays it here instead:
// ClipPosing). A pose file is
// turned into joint rotations here and goes over the wire. Errors (unreachable server, wrong token,
// unknown model, refused pose) throw with the server's address, the protocol error code and its
// reason.
//
// A request the server answers with UnknownModel or UnknownClip (a daemon that restarted with a
// store of its own, another replica behind HAProxy), or whose connection is lost, is asked again
// once, transparently: on a new connection for a lost one (client/reconnect.h), after the model
// is loaded again by its content id — its bytes uploaded again only to a server that lacks it
// (client/model_source.h) — and the clip uploaded again. Each such recovery is said on stderr.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "cli/posed_model.h"
#include "client/connection.h"
#include "client/model_source.h"
#include "deform/model/model.h"
#include "gpu/sheet/contact_sheet.h"
#include "motion/clip_poses.h"

namespace sweepd::cli {

struct ServerAddress {
  std::string address;    // HOST:PORT
  std::string token;      // the daemon's auth token ("" when it has none)
  client::ClientTls tls;  // --tls, --tls-ca, ... (client/client_tls_flags.h)
};

// What a remote position map asks for beyond its pose.
struct RemoteMapOptions {
  int size = 1024;
  bool normals = false;
  protocol::ExrCompression compression = protocol::ExrCompression::Zip;
  bool half_normals = false;
};

// Where a clip's frames are posed: by the server (uploaded once, frames asked for by number:
// pose, positionmap) or here, with the library's player (cli/posed_model.h: clip_player) on the
// served model, as the server would (metrics, which needs each frame's pose for the section
// planes it measures).
enum class ClipPosing { kOnServer, kHere };

class RemotePosedModel {
 public:
  // Connects, says Hello, loads or uploads the model and fetches its mesh; uploads the clip for
  // kOnServer, reads it for kHere. Throws.
  RemotePosedModel(const PosingArguments& arguments, const ServerAddress& server,
                   ClipPosing clip_posing = ClipPosing::kOnServer);
  ~RemotePosedModel();

  // The served model (rest pose); named after the local file's stem for an uploaded file,
  // as the local commands name it, else after the server's name for it.
  const deform::Model& model() const { return model_; }
  const PosingArguments& arguments() const { return arguments_; }
  // How the model was found, for the command's report: "uploaded", "already loaded", "server".
  const std::string& origin() const { return origin_; }
  // The command's report of the name the server holds the model under (ModelInfo.name: an
  // upload's file base name, or the name of the model it already held with the same bytes):
  // "model 'NAME' (id N) on sweepd at HOST:PORT (ORIGIN)".
  std::string served_as() const;
  // The clip's own frame rate (its file's, as the server read it); 0 without a clip.
  float clip_frames_per_second() const { return clip_frames_per_second_; }
  // The pose of clip frame `frame` (kHere), or the pose file / rest pose without a clip, for
  // measurements made here (`metrics --server`). Throws std::logic_error for a kOnServer clip.
  deform::Pose pose(int frame);
  // The server deforms `pose` with `method` and `features` (Sweep only): positions and
  // normals, vertex_count() each.
  void deform_pose(const deform::Pose& pose, deform::DeformMethod method,
                   protocol::Features features, std::vector<glm::vec3>& positions,
                   std::vector<glm::vec3>& normals);
  // Clip frame `frame` (the server's clip) or the pose file / rest pose, deformed by the
  // server with the arguments' method and features.
  void deform(int frame, std::vector<glm::vec3>& positions, std::vector<glm::vec3>& normals);
  // The server's OpenEXR position map of clip frame `frame` (P, A and N when asked for; the
  // server's 4-texel gutter); the EXR header's frame is `frame`.
  std::vector<std::uint8_t> position_map(int frame, const RemoteMapOptions& options);
  // The server's contact sheet of the clip's frames (ContactSheetRequest, protocol 1.11): the
  // grid `sweepctl sheet` draws here, drawn by the daemon. Needs a clip played on the server.
  sheet::SheetPicture contact_sheet(const sheet::SheetOptions& options);
  // The daemon's collision backend and its stage times since it started (Stats.collision,
  // protocol 1.3), as one line for the command's report; "" from an older server.
  std::string collision_summary();

 private:
  static protocol::Features features(const PosingArguments& arguments);
  protocol::PoseFields pose_fields(const deform::Pose& pose, deform::DeformMethod method,
                                   protocol::Features features);
  // Uploads the arguments' clip (UploadClip): --bvh's text, --clip-from's file, or for --clip
  // alone MODEL's own file (`local_model_file`: MODEL is a file here, a .glb/.gltf) played on
  // the model's own joints.
  const protocol::ClipInfo& upload_clip(client::Connection& connection, bool local_model_file);
  // The pose fields of `frame`: with a clip, only the model, method and features (the clip
  // gives the rest); else the pose's rotations.
  protocol::PoseFields frame_fields(int frame);
  // The clip frame `frame` in a request, or null without a clip.
  flatbuffers::Offset<protocol::ClipFrame> clip_frame(flatbuffers::FlatBufferBuilder& builder,
                                                      int frame) const;
  // `reply`'s positions and normals into the caller's arrays; throws when they do not match.
  void copy_vertices(const protocol::PosedVertices& reply, std::vector<glm::vec3>& positions,
                     std::vector<glm::vec3>& normals) const;
  // Sends what `send()` builds on connection_ and returns the reply as a Reply, asking once
  // more after set_up_again() (on a new connection when it was lost) for UnknownModel,
  // UnknownClip or a lost connection; a server Error throws with the address, code and reason.
  template <typename Reply, typename Send>
  const Reply& ask(const Send& send);
  // The model (by content id, uploaded again where missing) and the clip, on `connection`.
  void set_up_again(client::Connection& connection);

  PosingArguments arguments_;
  ServerAddress server_;
  std::unique_ptr<client::Connection> connection_;
  std::unique_ptr<client::ModelSource> source_;  // the model as every server gets it
  bool local_model_file_ = false;
  std::uint32_t model_id_ = 0;
  std::string origin_;
  std::string server_name_;
  deform::Model model_;
  std::string clip_id_;  // the server's id for the clip (kOnServer), else empty
  float clip_frames_per_second_ = 0.0f;
  std::unique_ptr<motion::ClipPoses> player_;  // the clip played here (kHere)
  std::optional<deform::Pose> file_pose_;
  std::vector<protocol::Quat> rotations_;  // wire scratch
  std::uint64_t sequence_ = 0;
};

}  // namespace sweepd::cli
