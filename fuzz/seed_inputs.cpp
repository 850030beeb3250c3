#include "fuzz/seed_inputs.h"

#include <lo/lo.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include "deform/binding/bind.h"
#include "deform/model/pose.h"
#include "deform/rig/rig_map.h"
#include "io/assimp/assimp_convert.h"
#include "io/gltf/gltf_save.h"
#include "io/json/pose_json.h"
#include "io/json/rig_map_json.h"
#include "io/sweepbind/sweepbind.h"
#include "mannequin/mannequin.h"
#include "protocol/messages.h"
#include "server/models/content_id.h"
#include "tests/io/fbx_binary.h"

namespace sweepd::fuzz {
namespace {

namespace fs = std::filesystem;
namespace pb = protocol;

Input read_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return Input(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

Input as_input(const std::string& text) { return Input(text.begin(), text.end()); }

// A JSON input for fuzz_json: its kind byte, then the text.
Input json_input(std::uint8_t kind, const std::string& text) {
  Input input(1 + text.size(), kind);
  std::copy(text.begin(), text.end(), input.begin() + 1);
  return input;
}

void append(Input& stream, std::span<const std::uint8_t> frame) {
  stream.insert(stream.end(), frame.begin(), frame.end());
}

// A session as a client sends it, cut into reads of `piece` bytes (fuzz_frames' first byte).
Input session(const deform::BoundModel& bound, const Input& glb, const std::string& bvh,
              std::uint8_t piece) {
  Input stream(1, piece);
  flatbuffers::FlatBufferBuilder builder;
  append(stream, pb::build_hello(builder, "token", "fuzz seed"));
  const deform::Pose rest = deform::rest_pose(bound.model.skeleton);
  std::vector<pb::Quat> rotations;
  for (const glm::quat& q : rest.local_rotations) rotations.emplace_back(q.x, q.y, q.z, q.w);
  pb::PoseFields fields;
  fields.model_id = 1;
  fields.sequence = 7;
  fields.rotations = rotations;
  fields.features = pb::Features::Folding | pb::Features::Volume;
  builder.Clear();
  append(stream, pb::finish_message(builder, pb::add_pose(builder, fields), 1));
  // The same pose into shared memory (1.10), at an offset inside the fuzz target's region.
  pb::PoseFields shared = fields;
  shared.shared_offset = 4096;
  builder.Clear();
  append(stream, pb::finish_message(builder, pb::add_pose(builder, shared), 1));
  builder.Clear();
  append(stream, pb::finish_message(builder, pb::CreateLoadModelDirect(builder, "seed", &glb), 2));
  const pb::Vec3 offset(0.001f, 0.0f, 0.0f);
  builder.Clear();
  append(stream, pb::finish_message(builder,
                                    pb::CreateEditKeyEllipseDirect(builder, 1, "left_arm", 1,
                                                                   &offset, 0.05f, 0.0f, 0.1f),
                                    3));
  builder.Clear();
  const auto map_pose = pb::add_pose(builder, fields);
  append(stream,
         pb::finish_message(builder, pb::CreatePositionMapRequest(builder, map_pose, 64, 64), 4));
  builder.Clear();
  append(stream,
         pb::finish_message(builder,
                            pb::CreateUploadClipDirect(builder, "seed.bvh", bvh.c_str(), 1.0f), 5));
  // Frame 1 of that clip (its id is its content id), as a pose and as a map; and two joints
  // turned by name.
  const std::string clip_id = server::clip_content_id(bvh, 1.0f);
  pb::PoseFields clip_fields;
  clip_fields.model_id = 1;
  clip_fields.sequence = 8;
  builder.Clear();
  auto pose = pb::add_pose(builder, clip_fields);
  auto clip = pb::CreateClipFrameDirect(builder, clip_id.c_str(), 1u);
  append(stream, pb::finish_message(builder, pb::CreatePoseFromClip(builder, pose, clip), 6));
  builder.Clear();
  pose = pb::add_pose(builder, clip_fields);
  clip = pb::CreateClipFrameDirect(builder, clip_id.c_str(), 1u);
  append(stream, pb::finish_message(
                     builder,
                     pb::CreatePositionMapRequest(builder, pose, 64, 64, pb::ExrCompression::Zip,
                                                  pb::MapLayers::Position, false, clip),
                     7));
  builder.Clear();
  pose = pb::add_pose(builder, clip_fields);
  const std::vector<std::string> names = {bound.model.skeleton.joints[1].name,
                                          bound.model.skeleton.joints[2].name};
  const std::vector<pb::Quat> turns = {pb::Quat(0.1f, 0.0f, 0.0f, 0.995f),
                                       pb::Quat(0.0f, 0.1f, 0.0f, 0.995f)};
  const auto by_name = pb::CreatePoseByName(builder, pose, builder.CreateVectorOfStrings(names),
                                            builder.CreateVectorOfStructs(turns));
  append(stream, pb::finish_message(builder, by_name, 8));
  // A contact sheet (1.11) of two frames of that clip, two methods, a close-up.
  builder.Clear();
  const std::vector<std::uint32_t> sheet_frames = {0, 1};
  const std::vector<std::string> sheet_methods = {"sweep", "lbs"};
  append(stream, pb::finish_message(builder,
                                    pb::CreateContactSheetRequest(
                                        builder, 1, builder.CreateString(clip_id),
                                        builder.CreateVector(sheet_frames),
                                        builder.CreateVectorOfStrings(sheet_methods), 64, 96,
                                        builder.CreateString("elbow_l"), true, 0.5f, 30.0f, 10.0f),
                                    9));
  return stream;
}

// A frames seed (fuzz_frames' input) as a --ws-listen client sends it: its upgrade request (a
// browser's, with an allowed Origin), then each frame as one binary message, masked as a client
// must with the key 0 (so the bytes stay readable and the seed the same on every run), cut into
// reads of `piece` bytes.
Input websocket_session(const Input& frames, std::uint8_t piece) {
  const std::string upgrade =
      "GET / HTTP/1.1\r\nHost: 127.0.0.1:7879\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
      "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n"
      "Origin: https://viewer.example\r\n\r\n";
  Input stream(1, piece);
  append(stream, as_input(upgrade));
  for (std::size_t at = 1; at + 4 <= frames.size();) {
    const std::size_t length = 4 + (frames[at] | frames[at + 1] << 8 | frames[at + 2] << 16 |
                                    static_cast<std::size_t>(frames[at + 3]) << 24);
    stream.push_back(0x82);  // FIN, binary
    // RFC 6455 5.2: the mask bit, then the length in 7 bits, or 126 and 16 bits, or 127 and 64.
    if (length < 126) {
      stream.push_back(static_cast<std::uint8_t>(0x80 | length));
    } else if (length <= 0xffff) {
      stream.insert(stream.end(), {0x80 | 126, static_cast<std::uint8_t>(length >> 8),
                                   static_cast<std::uint8_t>(length)});
    } else {
      stream.push_back(0x80 | 127);
      for (int shift = 56; shift >= 0; shift -= 8)
        stream.push_back(static_cast<std::uint8_t>(length >> shift));
    }
    stream.insert(stream.end(), 4, 0);  // the masking key
    stream.insert(stream.end(), frames.begin() + static_cast<std::ptrdiff_t>(at),
                  frames.begin() + static_cast<std::ptrdiff_t>(at + length));
    at += length;
  }
  return stream;
}

// A skeleton (the mannequin's, or a short chain) as a BVH clip of two frames (rest, then every
// joint turned a little).
std::string bvh_of(const deform::Skeleton& skeleton) {
  std::ostringstream text;
  text << "HIERARCHY\n";
  std::vector<int> depth(skeleton.joints.size(), 0);
  // Depth-first order is the skeleton's order when each joint's children follow it; the
  // mannequin is built that way. Close each joint's braces when the next one is shallower.
  for (std::size_t j = 0; j < skeleton.joints.size(); ++j) {
    const deform::Joint& joint = skeleton.joints[j];
    depth[j] = joint.parent < 0 ? 0 : depth[static_cast<std::size_t>(joint.parent)] + 1;
    const glm::vec3 t = joint.rest_translation * 100.0f;
    text << (joint.parent < 0 ? "ROOT " : "JOINT ") << joint.name << "\n{\n  OFFSET " << t.x << " "
         << t.y << " " << t.z << "\n  CHANNELS "
         << (joint.parent < 0 ? "6 Xposition Yposition Zposition " : "3 ")
         << "Zrotation Xrotation Yrotation\n";
    const int next_depth =
        j + 1 < skeleton.joints.size()
            ? (skeleton.joints[j + 1].parent < 0
                   ? 0
                   : depth[static_cast<std::size_t>(skeleton.joints[j + 1].parent)] + 1)
            : 0;
    if (next_depth <= depth[j]) text << "  End Site\n  {\n    OFFSET 0 5 0\n  }\n";
    for (int close = depth[j]; close >= next_depth; --close) text << "}\n";
  }
  text << "MOTION\nFrames: 2\nFrame Time: 0.0083333\n";
  for (int frame = 0; frame < 2; ++frame) {
    text << "0 90 0";
    for (std::size_t j = 0; j < skeleton.joints.size(); ++j) text << (frame ? " 5 -3 2" : " 0 0 0");
    text << "\n";
  }
  return text.str();
}

}  // namespace

// A VMC sender's frame as liblo writes it: the root, two bones (Unity's frame), then OK and T.
Input vmc_frame() {
  lo_bundle bundle = lo_bundle_new(LO_TT_IMMEDIATE);
  const auto transform = [](const char* name, float turn) {
    lo_message message = lo_message_new();
    lo_message_add_string(message, name);
    for (const float value : {0.0f, 0.9f, 0.0f, 0.0f, 0.0f, turn, 1.0f}) lo_message_add_float(message, value);
    return message;
  };
  lo_bundle_add_message(bundle, "/VMC/Ext/Root/Pos", transform("root", 0.0f));
  lo_bundle_add_message(bundle, "/VMC/Ext/Bone/Pos", transform("Hips", 0.1f));
  lo_bundle_add_message(bundle, "/VMC/Ext/Bone/Pos", transform("LeftUpperArm", 0.5f));
  lo_message ok = lo_message_new();
  lo_message_add_int32(ok, 1);
  lo_bundle_add_message(bundle, "/VMC/Ext/OK", ok);
  lo_message time = lo_message_new();
  lo_message_add_float(time, 0.5f);
  lo_bundle_add_message(bundle, "/VMC/Ext/T", time);
  std::size_t size = lo_bundle_length(bundle);
  Input bytes(size);
  lo_bundle_serialise(bundle, bytes.data(), &size);
  lo_bundle_free_recursive(bundle);
  return bytes;
}

std::map<std::string, std::vector<Input>> seed_inputs() {
  const deform::Model model = mannequin::make_mannequin({.target_vertices = 2000});
  const deform::RigMap rig = deform::detect_rig_map(model.skeleton);
  const deform::BoundModel bound = deform::bind(model, rig);
  const fs::path directory =
      fs::temp_directory_path() / ("sweepd_fuzz_seeds_" + std::to_string(getpid()));
  fs::create_directories(directory);
  io::save_gltf(model, directory / "m.glb");
  const Input glb = read_bytes(directory / "m.glb");
  io::save_rig_map_json(rig, model.skeleton, directory / "rig.json");
  deform::Pose pose = deform::rest_pose(model.skeleton);
  io::save_pose_json(pose, model.skeleton, directory / "pose.json");
  std::map<std::string, std::vector<Input>> seeds;
  const std::string bvh = bvh_of(model.skeleton);
  seeds["frames"] = {session(bound, glb, bvh, 255), session(bound, glb, bvh, 0)};
  seeds["websocket"] = {websocket_session(seeds["frames"][0], 255),
                        websocket_session(seeds["frames"][0], 0)};
  seeds["gltf"] = {glb};
  // The smallest mannequin as ASCII FBX (about 0.3 MB; made here, never committed).
  io::save_gltf(mannequin::make_mannequin({.target_vertices = mannequin::kMannequinMinVertices}),
                directory / "small.glb");
  // And a four-joint animation stack without a mesh (about 35 kB; the mannequin's FBX is
  // 0.3 MB, which libFuzzer runs about once a second): assimp's own BVH import, exported.
  deform::Skeleton chain;
  chain.joints = {{.name = "Hips", .rest_translation = {0.0f, 1.0f, 0.0f}},
                  {.name = "Spine", .parent = 0, .rest_translation = {0.0f, 0.3f, 0.0f}},
                  {.name = "Head", .parent = 1, .rest_translation = {0.0f, 0.3f, 0.0f}},
                  {.name = "LeftUpLeg", .parent = 0, .rest_translation = {0.1f, 0.0f, 0.0f}}};
  std::ofstream(directory / "chain.bvh") << bvh_of(chain);
  // Each also as binary FBX (tests/io/fbx_binary.h), for assimp's other tokenizer and parser.
  for (const char* source : {"small.glb", "chain.bvh"}) {
    const Input ascii = io::convert_with_assimp(directory / source, io::AssimpExport::kFbxMetres);
    seeds["fbx"].push_back(
        io::testing::binary_fbx_of({reinterpret_cast<const char*>(ascii.data()), ascii.size()}));
    seeds["fbx"].push_back(ascii);
  }
  seeds["bvh"] = {as_input(bvh)};
  seeds["sweepbind"] = {io::encode_sweepbind(bound)};
  const Input rig_bytes = read_bytes(directory / "rig.json");
  const Input pose_bytes = read_bytes(directory / "pose.json");
  seeds["json"] = {
      json_input(0, std::string(rig_bytes.begin(), rig_bytes.end())),
      json_input(1, std::string(pose_bytes.begin(), pose_bytes.end())),
      json_input(2, R"({"edits": [{"part": "left arm", "key": 1, "joint": "LeftForeArm",
        "samples": [{"angle": 90, "offset": [0, 0.01, 0], "rotation": [0, 0, 30],
                     "scale": [1.0, 1.1]}]}]})"),
      json_input(3, R"({"LFingers": "LeftHand", "Head": null})"),
      json_input(4, R"({"port": 7000, "max_models": 4, "token": "t"})")};
  seeds["vmc"] = {vmc_frame()};
  // Side-port requests as curl, Prometheus and a kubelet send them, whole at once (first byte
  // 255) and a byte at a time (0).
  for (const char* request :
       {"GET /readyz HTTP/1.1\r\nHost: 127.0.0.1:9464\r\nUser-Agent: kube-probe/1.29\r\n"
        "Accept: */*\r\nConnection: close\r\n\r\n",
        "GET /metrics HTTP/1.1\r\nHost: sweepd:9464\r\nAccept: text/plain;version=0.0.4\r\n"
        "Accept-Encoding: gzip\r\nX-Prometheus-Scrape-Timeout-Seconds: 10\r\n\r\n",
        "HEAD /viewer/viewer.js?ws=ws://127.0.0.1:7879 HTTP/1.0\n\n"}) {
    for (const std::uint8_t piece : {255, 0}) {
      Input input = as_input(request);
      input.insert(input.begin(), piece);
      seeds["http"].push_back(std::move(input));
    }
  }
  fs::remove_all(directory);
  return seeds;
}

}  // namespace sweepd::fuzz
