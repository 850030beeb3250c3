#include "cli/remote_posed_model.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "cli/served_model.h"
#include "client/bind_warnings.h"
#include "client/clip_upload.h"
#include "client/reconnect.h"
#include "io/files/file_bytes.h"
#include "io/json/pose_json.h"

namespace sweepd::cli {
namespace {

namespace pb = sweepd::protocol;

pb::DeformMethod wire_method(deform::DeformMethod method) {
  switch (method) {
    case deform::DeformMethod::kLbs:
      return pb::DeformMethod::Lbs;
    case deform::DeformMethod::kDqs:
      return pb::DeformMethod::Dqs;
    default:
      return pb::DeformMethod::Sweep;
  }
}

// The content id of the loaded model the server holds under `name`, or "" when none.
std::string content_loaded_on_server(client::Connection& connection, const std::string& name) {
  flatbuffers::FlatBufferBuilder& builder = connection.builder();
  builder.Clear();
  connection.send(pb::finish_message(builder, pb::CreateListModels(builder)));
  for (const pb::ModelSummary* model : *connection.expect<pb::ModelList>().models())
    if (model->model_id() != 0 && model->name()->str() == name)
      return model->content_id() ? model->content_id()->str() : "";
  return "";
}

std::runtime_error server_failure(const std::string& address, const client::ServerError& error) {
  return std::runtime_error("sweepd at " + address + ": " + error.what());
}

std::span<float> as_floats(std::vector<glm::vec3>& vectors) {
  static_assert(sizeof(glm::vec3) == 3 * sizeof(float));
  return {reinterpret_cast<float*>(vectors.data()), 3 * vectors.size()};
}

// The arguments, once MODEL is known to be an uploadable file or a server model name (checked
// before connecting).
const PosingArguments& checked_model(const PosingArguments& arguments) {
  const std::filesystem::path& file = arguments.model;
  const bool local_file = std::filesystem::is_regular_file(file);
  if (!local_file && file.has_parent_path())
    throw std::invalid_argument(file.string() +
                                ": no such file (a server model is named without a folder)");
  if (local_file && file.extension() == ".sweepbind")
    throw std::invalid_argument(file.string() +
                                ": a .sweepbind is not uploaded; give the .glb it was bound from");
  return arguments;
}

}  // namespace

template <typename Reply, typename Send>
const Reply& RemotePosedModel::ask(const Send& send) {
  for (bool again = false;; again = true) {
    try {
      send();
      return connection_->expect<Reply>();
    } catch (const client::ServerError& error) {
      const bool lost_model =
          error.code() == pb::ErrorCode::UnknownModel || error.code() == pb::ErrorCode::UnknownClip;
      if (again || !lost_model) throw server_failure(connection_->address(), error);
      std::fprintf(stderr, "sweepctl: sweepd at %s: %s; loading the model again\n",
                   connection_->address().c_str(), error.what());
      set_up_again(*connection_);
    } catch (const client::ConnectionLost& error) {
      if (again) throw;
      std::fprintf(stderr, "sweepctl: %s; connecting again\n", error.what());
      connection_ = client::reconnect(server_.address, server_.tls, [this](client::Connection& c) {
        c.hello(server_.token, "sweepctl");
        set_up_again(c);
      });
    }
  }
}

void RemotePosedModel::set_up_again(client::Connection& connection) {
  try {
    const int uploads = source_->uploads();
    model_id_ = source_->load(connection).model_id();
    if (source_->uploads() > uploads)
      std::fprintf(stderr, "sweepctl: uploaded %s again to sweepd at %s\n", source_->name().c_str(),
                   connection.address().c_str());
    if (!clip_id_.empty()) clip_id_ = upload_clip(connection, local_model_file_).clip_id()->str();
  } catch (const client::ServerError& error) {
    throw server_failure(connection.address(), error);
  }
}

RemotePosedModel::RemotePosedModel(const PosingArguments& arguments, const ServerAddress& server,
                                   ClipPosing clip_posing)
    : arguments_(checked_model(arguments)),
      server_(server),
      connection_(std::make_unique<client::Connection>(server.address, server.tls)) {
  try {
    connection_->hello(server.token, "sweepctl");
    const std::filesystem::path& file = arguments.model;
    local_model_file_ = std::filesystem::is_regular_file(file);
    const std::string name = local_model_file_ ? client::model_name_of_file(file) : file.string();
    const std::string rig = arguments.rig.empty() ? "" : io::read_file_text(arguments.rig);
    // The bytes are kept for a server that lacks the model later (restarted, another replica).
    source_ = std::make_unique<client::ModelSource>(
        name, local_model_file_ ? io::read_file_bytes(file) : std::vector<std::uint8_t>{}, rig,
        static_cast<std::uint8_t>(arguments.orientation));
    // A file is always sent with its bytes: a server holding them answers at once, without
    // binding. Asking by name alone would take another file of the same base name (one name
    // per model: /a/body.glb and /b/body.glb are both "body"); with the bytes, that is the
    // server's ModelLoadFailed naming the model that holds the name.
    const std::string listed =
        local_model_file_ ? content_loaded_on_server(*connection_, name) : std::string();
    const pb::ModelInfo& info = source_->load(*connection_);
    const std::string content_id = info.content_id() ? info.content_id()->str() : "";
    origin_ = !local_model_file_                        ? "server"
              : !listed.empty() && listed == content_id ? "already loaded"
                                                        : "uploaded";
    model_id_ = info.model_id();
    server_name_ = info.name()->str();
    // (1.14) The server's self-check of the binding: regions where the sweep is still worse
    // than skinning, as `sweepctl bind` prints them.
    client::print_bind_warnings(stderr, info);
    model_ = served_model(*connection_, info);                  // `info` is invalid from here on
    if (local_model_file_) model_.name = file.stem().string();  // as the local commands name it
    if (arguments.has_clip() && clip_posing == ClipPosing::kHere) {
      player_ = clip_player(arguments, model_);
      clip_frames_per_second_ = player_->motion().frames_per_second();
      if (arguments.fps <= 0.0f) require_clip_frames(arguments, player_->frame_count());
    } else if (arguments.has_clip()) {
      const pb::ClipInfo& clip = upload_clip(*connection_, local_model_file_);
      clip_id_ = clip.clip_id()->str();
      clip_frames_per_second_ = clip.frames_per_second();
      // The server's warnings: the reader's, and (1.12) what playing it on this model leaves
      // unmapped, as the local commands print the retargeter's.
      if (clip.warnings())
        for (const flatbuffers::String* warning : *clip.warnings())
          std::fprintf(stderr, "warning: %s: %s\n", arguments.clip_file().string().c_str(),
                       warning->c_str());
      if (arguments.fps <= 0.0f)
        require_clip_frames(arguments, static_cast<int>(clip.frame_count()));
    }
    if (!arguments.pose_file.empty())
      file_pose_ = io::load_pose_json(arguments.pose_file, model_.skeleton);
  } catch (const client::ServerError& error) {
    throw server_failure(server.address, error);
  }
}

const pb::ClipInfo& RemotePosedModel::upload_clip(client::Connection& connection,
                                                  bool local_model_file) {
  const PosingArguments& arguments = arguments_;
  const std::string map = arguments.bvh_map.empty() ? "" : io::read_file_text(arguments.bvh_map);
  if (!arguments.bvh.empty())
    return client::upload_clip(connection, arguments.bvh.filename().string(),
                               io::read_file_text(arguments.bvh), 1.0f, map, model_id_);
  if (!arguments.clip_from.empty())
    return client::upload_gltf_clip(connection, arguments.clip_from.filename().string(),
                                    io::read_file_bytes(arguments.clip_from), arguments.clip, false,
                                    map, model_id_);
  // --clip: an animation of MODEL's own file, played on its joints as they are.
  if (!local_model_file || arguments.model.extension() == ".sweepbind")
    throw std::invalid_argument(arguments.model.string() +
                                ": --clip plays an animation of the model's own glTF, FBX or "
                                "COLLADA file, uploaded from here; for another file's clip give "
                                "--clip-from FILE");
  return client::upload_gltf_clip(connection, arguments.model.filename().string(),
                                  io::read_file_bytes(arguments.model), arguments.clip, true, {},
                                  model_id_);
}

std::string RemotePosedModel::served_as() const {
  return "model '" + server_name_ + "' (id " + std::to_string(model_id_) + ") on sweepd at " +
         server_.address + " (" + origin_ + ")";
}

RemotePosedModel::~RemotePosedModel() {
  try {
    connection_->close("sweepctl done");
  } catch (const std::exception&) {
    // The server may already have closed the connection (e.g. after a fatal error).
  }
}

deform::Pose RemotePosedModel::pose(int frame) {
  if (!clip_id_.empty())
    throw std::logic_error("RemotePosedModel::pose: the clip is posed on the server (kOnServer)");
  if (player_) return clip_pose(arguments_, *player_, frame);
  if (file_pose_) return *file_pose_;
  return deform::rest_pose(model_.skeleton);
}

pb::Features RemotePosedModel::features(const PosingArguments& arguments) {
  pb::Features features = pb::Features::NONE;
  if (arguments.features.folding) features = features | pb::Features::Folding;
  if (arguments.features.protrusion) features = features | pb::Features::Protrusion;
  if (arguments.features.bulge) features = features | pb::Features::Bulge;
  if (arguments.features.volume) features = features | pb::Features::Volume;
  if (arguments.features.contact) features = features | pb::Features::Contact;
  return features;
}

pb::PoseFields RemotePosedModel::pose_fields(const deform::Pose& pose, deform::DeformMethod method,
                                             pb::Features features) {
  rotations_.clear();
  for (const glm::quat& q : pose.local_rotations) rotations_.emplace_back(q.x, q.y, q.z, q.w);
  pb::PoseFields fields;
  fields.model_id = model_id_;
  fields.sequence = ++sequence_;
  fields.rotations = rotations_;
  fields.root_translation =
      pb::Vec3(pose.root_translation.x, pose.root_translation.y, pose.root_translation.z);
  fields.method = wire_method(method);
  fields.features = features;
  return fields;
}

void RemotePosedModel::deform_pose(const deform::Pose& pose, deform::DeformMethod method,
                                   pb::Features features, std::vector<glm::vec3>& positions,
                                   std::vector<glm::vec3>& normals) {
  const auto send = [&] {
    pb::PoseFields fields = pose_fields(pose, method, features);
    fields.normals = true;
    flatbuffers::FlatBufferBuilder& builder = connection_->builder();
    builder.Clear();
    connection_->send(pb::finish_message(builder, pb::add_pose(builder, fields)));
  };
  copy_vertices(ask<pb::PosedVertices>(send), positions, normals);
}

void RemotePosedModel::deform(int frame, std::vector<glm::vec3>& positions,
                              std::vector<glm::vec3>& normals) {
  if (clip_id_.empty()) {
    deform_pose(pose(frame), arguments_.method, features(arguments_), positions, normals);
    return;
  }
  const auto send = [&] {
    pb::PoseFields fields = frame_fields(frame);
    fields.normals = true;
    flatbuffers::FlatBufferBuilder& builder = connection_->builder();
    builder.Clear();
    const auto request =
        pb::CreatePoseFromClip(builder, pb::add_pose(builder, fields), clip_frame(builder, frame));
    connection_->send(pb::finish_message(builder, request));
  };
  copy_vertices(ask<pb::PosedVertices>(send), positions, normals);
}

pb::PoseFields RemotePosedModel::frame_fields(int frame) {
  if (clip_id_.empty()) return pose_fields(pose(frame), arguments_.method, features(arguments_));
  pb::PoseFields fields;
  fields.model_id = model_id_;
  fields.sequence = ++sequence_;
  fields.method = wire_method(arguments_.method);
  fields.features = features(arguments_);
  return fields;
}

flatbuffers::Offset<pb::ClipFrame> RemotePosedModel::clip_frame(
    flatbuffers::FlatBufferBuilder& builder, int frame) const {
  if (clip_id_.empty()) return 0;
  const auto id = builder.CreateString(clip_id_);
  // --time, or --fps's frame at its time: the server samples the clip there (own rate).
  if (arguments_.time || arguments_.fps > 0.0f)
    return pb::CreateClipFrame(builder, id, flatbuffers::nullopt,
                               arguments_.time ? *arguments_.time : frame / double{arguments_.fps});
  return pb::CreateClipFrame(builder, id, static_cast<std::uint32_t>(frame));
}

void RemotePosedModel::copy_vertices(const pb::PosedVertices& reply,
                                     std::vector<glm::vec3>& positions,
                                     std::vector<glm::vec3>& normals) const {
  positions.resize(model_.vertex_count());
  normals.resize(model_.vertex_count());
  if (reply.vertex_count() != model_.vertex_count() ||
      !pb::copy_positions(reply, as_floats(positions)) ||
      !pb::copy_normals(reply, as_floats(normals)))
    throw std::runtime_error("sweepd at " + connection_->address() +
                             ": PosedVertices do not match the model's " +
                             std::to_string(model_.vertex_count()) + " vertices");
}

std::vector<std::uint8_t> RemotePosedModel::position_map(int frame,
                                                         const RemoteMapOptions& options) {
  const auto send = [&] {
    pb::PoseFields fields = frame_fields(frame);
    fields.sequence = static_cast<std::uint64_t>(frame);  // the EXR header's "frame"
    const pb::MapLayers layers = pb::MapLayers::Position | pb::MapLayers::Coverage |
                                 (options.normals ? pb::MapLayers::Normal : pb::MapLayers::NONE);
    const auto side = static_cast<std::uint32_t>(options.size);
    flatbuffers::FlatBufferBuilder& builder = connection_->builder();
    builder.Clear();
    const auto pose = pb::add_pose(builder, fields);
    const auto request =
        pb::CreatePositionMapRequest(builder, pose, side, side, options.compression, layers,
                                     options.half_normals, clip_frame(builder, frame));
    connection_->send(pb::finish_message(builder, request));
  };
  const pb::PositionMap& reply = ask<pb::PositionMap>(send);
  return {reply.exr()->begin(), reply.exr()->end()};
}

sheet::SheetPicture RemotePosedModel::contact_sheet(const sheet::SheetOptions& options) {
  if (clip_id_.empty())
    throw std::logic_error("a contact sheet on the server needs its clip there");
  const auto send = [&] {
    flatbuffers::FlatBufferBuilder& builder = connection_->builder();
    builder.Clear();
    std::vector<std::uint32_t> frames(options.frames.begin(), options.frames.end());
    std::vector<std::string> methods;
    for (const deform::MethodChoice& m : options.methods) methods.push_back(m.name);
    const auto request = pb::CreateContactSheetRequest(
        builder, model_id_, builder.CreateString(clip_id_), builder.CreateVector(frames),
        builder.CreateVectorOfStrings(methods), static_cast<std::uint16_t>(options.cell_width),
        static_cast<std::uint16_t>(options.cell_height), builder.CreateString(options.focus),
        options.heat, options.heat_full_scale, options.azimuth_degrees, options.elevation_degrees);
    connection_->send(pb::finish_message(builder, request));
  };
  const pb::ContactSheet& reply = ask<pb::ContactSheet>(send);
  sheet::SheetPicture picture;
  picture.width = static_cast<int>(reply.width());
  picture.height = static_cast<int>(reply.height());
  if (reply.png()) picture.png.assign(reply.png()->begin(), reply.png()->end());
  picture.renderer = reply.renderer() ? reply.renderer()->str() : "";
  const std::size_t cells = options.frames.size() * options.methods.size();
  // A server before protocol 1.16 sends no ratios, only |l / l_rest - 1|.
  const auto* shortest = reply.shortest_edge_ratio();
  const auto* longest = reply.longest_edge_ratio();
  const std::size_t figures = shortest && longest ? std::min(shortest->size(), longest->size()) : 0;
  if (picture.png.empty() || figures != cells)
    throw std::runtime_error("sweepd at " + connection_->address() + ": its contact sheet has " +
                             std::to_string(figures) + " cells' edge length ratios for " +
                             std::to_string(cells) + " cells" +
                             (picture.png.empty() ? " and no PNG" : "") +
                             (figures == 0 ? " (a server before protocol 1.16 sends none)" : ""));
  for (std::size_t i = 0; i < cells; ++i)
    picture.edge_ratios.push_back({shortest->Get(i), longest->Get(i)});
  return picture;
}

std::string RemotePosedModel::collision_summary() {
  const auto send = [&] {
    flatbuffers::FlatBufferBuilder& builder = connection_->builder();
    builder.Clear();
    connection_->send(pb::finish_message(builder, pb::CreateStatsRequest(builder)));
  };
  const pb::CollisionStats* collision = ask<pb::Stats>(send).collision();
  if (collision == nullptr) return "";
  using std::chrono::nanoseconds;
  const auto text = [](const flatbuffers::String* s) { return s == nullptr ? "" : s->str(); };
  return describe_collision(
      text(collision->backend()) == "gpu" ? gpu::CollisionBackend::kGpu
                                          : gpu::CollisionBackend::kCpu,
      " on sweepd at " + connection_->address(), text(collision->reason()),
      std::to_string(collision->requests()) + " poses since it started, " +
          std::to_string(collision->gpu_fallbacks()) + " GPU fallbacks",
      {nanoseconds(collision->detect_ns()), nanoseconds(collision->fold_ns()),
       nanoseconds(collision->protrude_ns()), nanoseconds(collision->contact_ns())},
      {nanoseconds(collision->upload_ns()), nanoseconds(collision->readback_ns()),
       nanoseconds(collision->dispatch_ns())});
}

}  // namespace sweepd::cli
