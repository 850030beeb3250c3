#include "fuzz/fuzz_inputs.h"

#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>

#include "deform/binding/bind.h"
#include "deform/edits/rest_key_edit.h"
#include "deform/job/deform_job.h"
#include "deform/rig/human_body_bones.h"
#include "deform/rig/rig_map.h"
#include "io/assimp/assimp_clip_load.h"
#include "io/assimp/assimp_load.h"
#include "io/bvh/bvh_load.h"
#include "io/gltf/gltf_load.h"
#include "io/json/joint_name_map_json.h"
#include "io/json/key_ellipse_edits_json.h"
#include "io/json/pose_json.h"
#include "io/json/rig_map_json.h"
#include "io/sweepbind/sweepbind.h"
#include "mannequin/mannequin.h"
#include "protocol/framing.h"
#include "server/config.h"
#include "server/handlers/edit_key_ellipse_handler.h"
#include "server/handlers/load_model_handler.h"
#include "server/handlers/pose_intake.h"
#include "server/handlers/pose_request.h"
#include "server/models/clip_store.h"
#include "server/services/contact_sheet_service.h"
#include "server/services/position_map_service.h"
#include "server/services/vmc/osc_packet.h"
#include "server/services/vmc/vmc_stream.h"
#include "server/transport/websocket_session.h"

namespace sweepd::fuzz {
namespace {

namespace fs = std::filesystem;

// The small mannequin, bound once: the model poses, edits and JSON inputs are read against.
const server::ModelHandle& model() {
  static const server::ModelHandle handle = [] {
    auto registered = std::make_shared<server::RegisteredModel>();
    const deform::Model mannequin = mannequin::make_mannequin({.target_vertices = 2000});
    registered->id = 1;
    registered->name = "mannequin";
    registered->bound = deform::bind(mannequin, deform::detect_rig_map(mannequin.skeleton));
    registered->runtime = std::make_shared<const deform::ModelRuntime>(registered->bound);
    return server::ModelHandle(registered);
  }();
  return handle;
}

// The loaders that read files get the bytes through a scratch file of this process, removed
// once the loader is done (the test of this file runs every seed; nothing may stay in /tmp).
class ScratchFile {
 public:
  ScratchFile(std::span<const std::uint8_t> bytes, const std::string& extension)
      : path_(fs::temp_directory_path() / ("sweepd_fuzz_" + std::to_string(getpid()) + extension)) {
    std::ofstream(path_, std::ios::binary | std::ios::trunc)
        .write(reinterpret_cast<const char*>(bytes.data()),
               static_cast<std::streamsize>(bytes.size()));
  }
  ~ScratchFile() {
    std::error_code ignored;
    fs::remove(path_, ignored);
  }
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// Runs `parse`: true when it went through, false for a clean refusal (a std::exception).
template <typename Parse>
bool accepted(Parse&& parse) {
  try {
    parse();
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

// The models a fuzzed pose may name: the mannequin, as id 1.
class OneModel : public server::ModelLookup {
 public:
  server::ModelHandle find(std::uint32_t id) const override { return id == 1 ? model() : nullptr; }
  std::vector<server::ModelHandle> held_models() const override { return {model()}; }
};

// A pose intake's outcome deformed as the daemon's worker would, or its refusal thrown.
void deform(std::variant<server::PoseRequest, server::RequestError> intake) {
  if (const auto* error = std::get_if<server::RequestError>(&intake))
    throw std::invalid_argument(error->message);
  server::PoseRequest& request = std::get<server::PoseRequest>(intake);
  // A pose into shared memory (1.10) placed as the daemon places it, in a region of 1 MiB:
  // fuzzed offsets and sizes meet its bounds check, and what passes is written there.
  static const std::shared_ptr<const server::SharedRegion> region =
      server::SharedRegion::create(1u << 20);
  if (auto error = server::place_in_shared_region(request, region))
    throw std::invalid_argument(error->message);
  const std::size_t vertices = model()->bound.model.vertex_count();
  std::vector<glm::vec3> positions(vertices);
  std::span<glm::vec3> out = positions;
  if (request.shared_region) {
    const std::span<float> floats = *region->floats(*request.shared_offset, 3 * vertices);
    out = {reinterpret_cast<glm::vec3*>(floats.data()), vertices};
  }
  thread_local deform::DeformContext context;
  request.job(1, out, {}).run_validated(context);
}

// One message of a frames input, against the clips uploaded earlier in the same input.
void decode_message(const protocol::Message& message, server::ClipStore& clips) {
  const OneModel models;
  switch (message.body_type()) {
    case protocol::Body::Pose:
      deform(server::read_pose_message(models, *message.body_as_Pose(), 1));
      break;
    case protocol::Body::PoseFromClip: {
      const protocol::PoseFromClip& request = *message.body_as_PoseFromClip();
      if (!request.pose() || !request.clip()) throw std::invalid_argument("no pose or clip");
      deform(server::read_clip_pose_message(models, clips, *request.pose(), *request.clip(), 1));
      break;
    }
    case protocol::Body::PoseByName: {
      // As handle_pose_by_name: a PoseByName without its pose is refused before the intake.
      const protocol::PoseByName& request = *message.body_as_PoseByName();
      if (!request.pose()) throw std::invalid_argument("no pose");
      deform(server::read_named_pose_message(models, request, 1));
      break;
    }
    case protocol::Body::LoadModel:
      server::read_load_model(*message.body_as_LoadModel());
      break;
    case protocol::Body::EditKeyEllipse: {
      const server::KeyEllipseEditWork work =
          server::read_key_ellipse_edit(*message.body_as_EditKeyEllipse());
      deform::BoundModel copy = model()->bound;
      if (std::string problem = deform::apply_rest_key_edit(copy, work.edit); !problem.empty())
        throw std::invalid_argument(problem);
      break;
    }
    case protocol::Body::PositionMapRequest: {
      // Its pose deformed as for a Pose or a clip frame; the map's rendering is the GPU's.
      const protocol::PositionMapRequest& map = *message.body_as_PositionMapRequest();
      if (!map.pose()) throw std::invalid_argument("no pose");
      deform(map.clip()
                 ? server::read_clip_pose_message(models, clips, *map.pose(), *map.clip(), 1, &map)
                 : server::read_pose_message(models, *map.pose(), 1, &map));
      break;
    }
    case protocol::Body::ContactSheetRequest: {
      // Read as the I/O thread reads it; what passes gets the sheet's framing pass (an LBS
      // deformation per frame, cameras); the cells' rendering is the GPU's.
      auto read =
          server::read_contact_sheet_request(models, clips, *message.body_as_ContactSheetRequest());
      if (const auto* error = std::get_if<server::RequestError>(&read))
        throw std::invalid_argument(error->message);
      const server::SheetWork& work = std::get<server::SheetWork>(read);
      const sheet::ContactSheet framed(
          work.sheet_model(), work.options, nullptr,
          [](const gpu::PreviewMesh&, const gpu::PreviewOptions&, std::span<std::uint8_t>) {});
      break;
    }
    case protocol::Body::UploadClip: {
      // As the daemon's worker takes it, into the input's own store (inputs do not fill one
      // another's room; a later PoseFromClip of the input finds it).
      const protocol::UploadClip& upload = *message.body_as_UploadClip();
      const auto added = clips.add(server::ClipUpload::of_message(upload), models);
      if (const auto* error = std::get_if<server::RequestError>(&added))
        throw std::invalid_argument(error->message);
      break;
    }
    default:
      break;
  }
}

// One connection's frames as the daemon reads them (a shared BufferBudget, its own clip store),
// every whole frame decoded, whatever happened to the ones before.
class ConnectionFrames {
 public:
  void read(std::span<const std::uint8_t> input) {
    for (protocol::FrameEvent event = reader_.read(input);
         event.status != protocol::FrameStatus::kPending; event = reader_.read(input)) {
      const bool decoded = event.status == protocol::FrameStatus::kFrame &&
                           accepted([&] { decode_message(*event.message, clips_); });
      whole_ = whole_ && decoded;
      ++frames_;
    }
  }
  // Every frame so far whole and decoded, and none begun and not ended.
  bool whole() const { return whole_ && !reader_.mid_frame(); }
  std::size_t frames() const { return frames_; }

 private:
  protocol::BufferBudget budget_{1 << 20};
  protocol::FrameReader reader_{256 * 1024, &budget_};
  server::ClipStore clips_{2, server::ServerConfig{}.max_clip_bytes};
  bool whole_ = true;
  std::size_t frames_ = 0;
};

// The first byte of `bytes` cuts the rest into reads (read_bytes); each piece goes to `read`,
// which returns false to stop reading.
template <typename Read>
void in_pieces(std::span<const std::uint8_t> bytes, Read&& read) {
  const std::size_t piece = read_bytes(bytes[0], bytes.size() - 1);
  bytes = bytes.subspan(1);
  for (std::size_t at = 0; at < bytes.size(); at += piece)
    if (!read(bytes.subspan(at, std::min(piece, bytes.size() - at)))) return;
}

}  // namespace

void prepare() { model(); }

std::size_t read_bytes(std::uint8_t first_byte, std::size_t input_bytes) {
  const std::size_t fewest = (input_bytes + kMostReads - 1) / kMostReads;
  return std::max(static_cast<std::size_t>(first_byte) + 1, fewest);
}

bool fuzz_frames(std::span<const std::uint8_t> bytes) {
  if (bytes.empty()) return false;
  ConnectionFrames frames;
  in_pieces(bytes, [&](std::span<const std::uint8_t> input) {
    frames.read(input);
    return true;
  });
  return frames.whole();
}

bool fuzz_websocket(std::span<const std::uint8_t> bytes) {
  if (bytes.empty()) return false;
  // As --ws-listen takes a connection: a server session (an allowed Origin, as with
  // --ws-allowed-origin; a message of at most 256 KiB, the frame limit fuzz_frames reads with).
  server::WebSocketSession session(server::WebSocketSession::Role::kServer,
                                   {"https://viewer.example"},
                                   256 * 1024 + protocol::kLengthPrefixBytes);
  ConnectionFrames frames;
  in_pieces(bytes, [&](std::span<const std::uint8_t> input) {
    session.receive(input.data(), input.size());
    session.outgoing().clear();  // what the daemon would write back: the handshake, pongs
    std::vector<std::uint8_t>& payload = session.payload();
    frames.read(payload);
    payload.clear();
    // The daemon reads no more of a session that has ended.
    return session.state() != server::WebSocketSession::State::kEnded;
  });
  // Accepted: the session open, and frames carried in it, every one whole and decoded.
  return session.state() == server::WebSocketSession::State::kOpen && !session.mid_message() &&
         frames.frames() > 0 && frames.whole();
}

bool fuzz_gltf(std::span<const std::uint8_t> bytes) {
  const ScratchFile file(bytes, ".glb");
  return accepted([&] { io::load_gltf(file.path(), io::GltfUriPolicy::self_contained()); });
}

bool fuzz_fbx(std::span<const std::uint8_t> bytes) {
  // The model, then its first animation as a clip (an upload's UploadClip reads the same bytes).
  const bool model = accepted([&] { io::load_assimp(bytes, "fuzz.fbx"); });
  const bool clip = accepted([&] { io::load_assimp_clip(bytes, "fuzz.fbx", "0"); });
  return model || clip;
}

bool fuzz_bvh(std::span<const std::uint8_t> bytes) {
  const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  return accepted([&] { io::parse_bvh(text, "fuzz.bvh"); });
}

bool fuzz_sweepbind(std::span<const std::uint8_t> bytes) {
  return accepted([&] { io::decode_sweepbind(bytes, "fuzz.sweepbind"); });
}

bool fuzz_json(std::span<const std::uint8_t> bytes) {
  if (bytes.empty()) return false;
  const std::uint8_t kind = bytes[0] % 5;
  const ScratchFile scratch(bytes.subspan(1), ".json");
  const fs::path& file = scratch.path();
  const deform::Skeleton& skeleton = model()->bound.model.skeleton;
  return accepted([&] {
    switch (kind) {
      case 0:
        io::load_rig_map_json(file, skeleton);
        break;
      case 1:
        io::load_pose_json(file, skeleton);
        break;
      case 2:
        io::load_key_ellipse_edits_json(file, model()->bound);
        break;
      case 3:
        io::load_joint_name_map_json(file);
        break;
      default: {
        server::ServerConfig config;
        server::apply_config_file(file, config);
      }
    }
  });
}

bool fuzz_vmc(std::span<const std::uint8_t> bytes) {
  std::vector<std::byte> datagram(bytes.size());
  std::memcpy(datagram.data(), bytes.data(), bytes.size());
  const std::optional<server::OscPacket> packet = server::read_osc_packet(datagram);
  if (!packet) return false;
  server::VmcStream stream;
  server::VmcCounters counters;
  stream.apply(*packet, counters);
  const deform::BoundModel& bound = model()->bound;
  server::PoseRequest request;
  request.model = model();
  request.pose = stream.pose_for(bound.model.skeleton,
                                 deform::map_human_body_bones(bound.model.skeleton, bound.rig));
  if (const deform::JobProblem problem = request.job(0, {}, {}).validate()) return false;
  deform(request);
  return counters.dropped_messages == 0;
}

}  // namespace sweepd::fuzz
