// Tests for protocol/messages.h and the schema: every message type survives builder →
// frame → FrameReader fed in random-sized chunks; the zero-copy PosedVertices frame; the
// pose checks a server answers with Error codes.
#include "protocol/messages.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <span>
#include <vector>

#include "protocol/float16.h"
#include "protocol/framing.h"

namespace sweepd::protocol {
namespace {

using Bytes = std::vector<std::uint8_t>;
using flatbuffers::FlatBufferBuilder;

Bytes copy_of(std::span<const std::uint8_t> frame) { return {frame.begin(), frame.end()}; }

// The one frame `bytes` hold, read as a server reads a socket; valid while `reader` is.
FrameEvent read_single(FrameReader& reader, const Bytes& bytes) {
  std::span<const std::uint8_t> input(bytes);
  FrameEvent event = reader.read(input);
  EXPECT_TRUE(input.empty());
  return event;
}

// Zero copy: an array handed out for writing lies inside the outgoing frame's own bytes.
void expect_inside_frame(const void* array, std::size_t array_bytes,
                         std::span<const std::uint8_t> frame) {
  const auto* begin = static_cast<const std::uint8_t*>(array);
  EXPECT_GE(begin, frame.data());
  EXPECT_LE(begin + array_bytes, frame.data() + frame.size());
}

const std::vector<Quat> kRotations = {Quat(0, 0, 0, 1), Quat(0.5f, 0.5f, 0.5f, 0.5f),
                                      Quat(0, 0.70710678f, 0, 0.70710678f)};

PoseFields three_joint_pose() {
  PoseFields fields;
  fields.model_id = 4;
  fields.sequence = 1001;
  fields.client_time_ns = 123456789012345ull;
  fields.rotations = kRotations;
  fields.root_translation = Vec3(0.1f, 0.9f, -0.2f);
  fields.method = DeformMethod::Dqs;
  fields.features = Features::Folding | Features::Volume;
  fields.positions = PositionFormat::Float16;
  fields.normals = true;
  return fields;
}

void expect_three_joint_pose(const Pose& pose) {
  EXPECT_EQ(pose.model_id(), 4u);
  EXPECT_EQ(pose.sequence(), 1001u);
  EXPECT_EQ(pose.client_time_ns(), 123456789012345ull);
  ASSERT_EQ(pose.rotations()->size(), kRotations.size());
  for (flatbuffers::uoffset_t j = 0; j < kRotations.size(); ++j) {
    EXPECT_EQ(pose.rotations()->Get(j)->y(), kRotations[j].y());
    EXPECT_EQ(pose.rotations()->Get(j)->w(), kRotations[j].w());
  }
  EXPECT_EQ(pose.root_translation()->y(), 0.9f);
  EXPECT_EQ(pose.method(), DeformMethod::Dqs);
  EXPECT_EQ(pose.features(), Features::Folding | Features::Volume);
  EXPECT_EQ(pose.positions(), PositionFormat::Float16);
  EXPECT_TRUE(pose.normals());
}

// One message of each Body type: how to build it, and what must come out the other side.
struct Sample {
  Body type;
  std::function<std::span<const std::uint8_t>(FlatBufferBuilder&)> build;
  std::function<void(const Message&)> check;
};

std::vector<Sample> one_of_each_body() {
  const LatencyPercentiles latency(1000, 2000, 5000, 9000);
  return {
      {Body::Hello,
       [](FlatBufferBuilder& b) {
         return build_hello(b, "s3cret", "pose-streamer", PoseDelivery::LatestWins, 1);
       },
       [](const Message& m) {
         const Hello* hello = m.body_as_Hello();
         EXPECT_EQ(hello->version_major(), kProtocolVersionMajor);
         EXPECT_EQ(hello->version_minor(), kProtocolVersionMinor);
         EXPECT_EQ(hello->auth_token()->str(), "s3cret");
         EXPECT_EQ(hello->delivery(), PoseDelivery::LatestWins);
       }},
      {Body::Welcome,
       [](FlatBufferBuilder& b) {
         const auto capabilities = b.CreateVectorOfStrings({"sweep", "lbs", "float16"});
         return finish_message(b,
                               CreateWelcome(b, 1, 0, b.CreateString("sweepd"), capabilities,
                                             kDefaultMaxFrameBytes, 8, 77),
                               1);
       },
       [](const Message& m) {
         const Welcome* welcome = m.body_as_Welcome();
         ASSERT_EQ(welcome->capabilities()->size(), 3u);
         EXPECT_EQ(welcome->capabilities()->Get(2)->str(), "float16");
         EXPECT_EQ(welcome->max_frame_bytes(), kDefaultMaxFrameBytes);
         EXPECT_EQ(welcome->connection_id(), 77u);
       }},
      {Body::Bye,
       [](FlatBufferBuilder& b) { return finish_message(b, CreateByeDirect(b, "done")); },
       [](const Message& m) { EXPECT_EQ(m.body_as_Bye()->reason()->str(), "done"); }},
      {Body::ListModels,
       [](FlatBufferBuilder& b) { return finish_message(b, CreateListModels(b), 2); },
       [](const Message& m) { EXPECT_NE(m.body_as_ListModels(), nullptr); }},
      {Body::ModelList,
       [](FlatBufferBuilder& b) {
         std::vector<flatbuffers::Offset<ModelSummary>> models = {
             CreateModelSummaryDirect(b, 1, "mannequin", 72000, 22),
             CreateModelSummaryDirect(b, 0, "male.glb")};
         return finish_message(b, CreateModelListDirect(b, &models), 2);
       },
       [](const Message& m) {
         const auto* models = m.body_as_ModelList()->models();
         ASSERT_EQ(models->size(), 2u);
         EXPECT_EQ(models->Get(0)->vertex_count(), 72000u);
         EXPECT_EQ(models->Get(1)->name()->str(), "male.glb");
         EXPECT_EQ(models->Get(1)->model_id(), 0u);
       }},
      {Body::LoadModel,
       [](FlatBufferBuilder& b) {
         const std::vector<std::uint8_t> glb = {'g', 'l', 'T', 'F', 2, 0, 0, 0};
         const auto options = CreateBindOptionsDirect(b, "{\"torso\": []}", 3);
         return finish_message(b, CreateLoadModelDirect(b, "upload", &glb, options), 3);
       },
       [](const Message& m) {
         const LoadModel* load = m.body_as_LoadModel();
         ASSERT_EQ(load->gltf()->size(), 8u);
         EXPECT_EQ(load->gltf()->Get(3), 'F');
         EXPECT_EQ(load->options()->keys_per_link(), 3);
         EXPECT_EQ(load->options()->rig_map_json()->str(), "{\"torso\": []}");
       }},
      {Body::ModelInfo,
       [](FlatBufferBuilder& b) {
         const auto joints = b.CreateVectorOfStrings({"Hips", "Spine", "Head"});
         const auto parents = b.CreateVector(std::vector<std::int32_t>{-1, 0, 1});
         const auto bind = CreateBindSummaryDirect(b, "mixamo", 6, 30, 60000, 12000, 2500000);
         return finish_message(b,
                               CreateModelInfo(b, 5, b.CreateString("male"), joints, parents, 72000,
                                               143000, true, bind),
                               3);
       },
       [](const Message& m) {
         const ModelInfo* info = m.body_as_ModelInfo();
         EXPECT_EQ(info->model_id(), 5u);
         ASSERT_EQ(info->joint_names()->size(), 3u);
         EXPECT_EQ(info->joint_names()->Get(1)->str(), "Spine");
         EXPECT_EQ(info->joint_parents()->Get(0), -1);
         EXPECT_TRUE(info->has_uvs());
         EXPECT_EQ(info->bind()->rig_convention()->str(), "mixamo");
         EXPECT_EQ(info->bind()->skinned_vertex_count(), 12000u);
       }},
      {Body::Pose,
       [](FlatBufferBuilder& b) { return finish_message(b, add_pose(b, three_joint_pose())); },
       [](const Message& m) { expect_three_joint_pose(*m.body_as_Pose()); }},
      {Body::PosedVertices,
       [](FlatBufferBuilder& b) {
         PosedVerticesFrame frame(b, {.request_id = 0,
                                      .model_id = 4,
                                      .sequence = 1001,
                                      .vertex_count = 2,
                                      .dropped_before = 3});
         const float xyz[6] = {0, 1, 2, 3, 4, 5};
         std::copy(xyz, xyz + 6, frame.positions_f32().begin());
         frame.timings().mutate_deform_ns(400000);
         return frame.bytes();
       },
       [](const Message& m) {
         const PosedVertices* reply = m.body_as_PosedVertices();
         EXPECT_EQ(reply->sequence(), 1001u);
         EXPECT_EQ(reply->dropped_before(), 3u);
         EXPECT_EQ(reply->timings()->deform_ns(), 400000u);
         float xyz[6];
         ASSERT_TRUE(copy_positions(*reply, xyz));
         EXPECT_EQ(xyz[5], 5.0f);
       }},
      {Body::PositionMapRequest,
       [](FlatBufferBuilder& b) {
         const auto pose = add_pose(b, three_joint_pose());
         return finish_message(b,
                               CreatePositionMapRequest(b, pose, 2048, 1024, ExrCompression::Piz,
                                                        MapLayers::Position | MapLayers::Normal),
                               9);
       },
       [](const Message& m) {
         const PositionMapRequest* request = m.body_as_PositionMapRequest();
         expect_three_joint_pose(*request->pose());
         EXPECT_EQ(request->width(), 2048u);
         EXPECT_EQ(request->height(), 1024u);
         EXPECT_EQ(request->compression(), ExrCompression::Piz);
         EXPECT_EQ(request->layers(), MapLayers::Position | MapLayers::Normal);
       }},
      {Body::PositionMap,
       [](FlatBufferBuilder& b) {
         const std::vector<std::uint8_t> exr = {0x76, 0x2f, 0x31, 0x01};  // EXR magic
         const ServerTimings timings(1, 2, 3, 4);
         return finish_message(b, CreatePositionMapDirect(b, 4, 1001, 2048, 1024, &exr, &timings),
                               9);
       },
       [](const Message& m) {
         const PositionMap* map = m.body_as_PositionMap();
         ASSERT_EQ(map->exr()->size(), 4u);
         EXPECT_EQ(map->exr()->Get(0), 0x76);
         EXPECT_EQ(map->timings()->encode_ns(), 4u);
       }},
      {Body::EditKeyEllipse,
       [](FlatBufferBuilder& b) {
         const Vec3 offset(0.01f, 0, 0);
         return finish_message(
             b, CreateEditKeyEllipseDirect(b, 4, "left_arm", 2, &offset, 0.05f, 0.04f, 0.1f));
       },
       [](const Message& m) {
         const EditKeyEllipse* edit = m.body_as_EditKeyEllipse();
         EXPECT_EQ(edit->sweep()->str(), "left_arm");
         EXPECT_EQ(edit->key_index(), 2u);
         EXPECT_EQ(edit->centre_offset()->x(), 0.01f);
         EXPECT_EQ(edit->half_axis_b(), 0.04f);
         EXPECT_EQ(edit->twist_radians(), 0.1f);
       }},
      {Body::StatsRequest,
       [](FlatBufferBuilder& b) { return finish_message(b, CreateStatsRequest(b), 11); },
       [](const Message& m) { EXPECT_EQ(m.request_id(), 11u); }},
      {Body::Stats,
       [latency](FlatBufferBuilder& b) {
         std::vector<flatbuffers::Offset<ModelStats>> models = {
             CreateModelStatsDirect(b, 4, "male", 500, 2, &latency)};
         std::vector<flatbuffers::Offset<ConnectionStats>> connections = {
             CreateConnectionStatsDirect(b, 77, "127.0.0.1:50000", "pose-streamer", 510, 500, 8, 2,
                                         30000, 9000000, &latency)};
         return finish_message(b, CreateStatsDirect(b, 60000000000ull, &models, &connections), 11);
       },
       [](const Message& m) {
         const Stats* stats = m.body_as_Stats();
         EXPECT_EQ(stats->uptime_ns(), 60000000000ull);
         EXPECT_EQ(stats->models()->Get(0)->deform_latency()->p99_ns(), 5000u);
         const ConnectionStats* connection = stats->connections()->Get(0);
         EXPECT_EQ(connection->poses_dropped(), 8u);
         EXPECT_EQ(connection->peer()->str(), "127.0.0.1:50000");
         EXPECT_EQ(connection->server_latency()->max_ns(), 9000u);
       }},
      {Body::Error,
       [](FlatBufferBuilder& b) {
         return build_error(b, ErrorCode::WrongJointCount, "pose 1001 has 3 rotations", 1001, 0,
                            false);
       },
       [](const Message& m) {
         const Error* error = m.body_as_Error();
         EXPECT_EQ(error->code(), ErrorCode::WrongJointCount);
         EXPECT_EQ(error->message()->str(), "pose 1001 has 3 rotations");
         EXPECT_EQ(error->sequence(), 1001u);
         EXPECT_FALSE(error->fatal());
       }},
      {Body::MeshRequest,
       [](FlatBufferBuilder& b) { return finish_message(b, CreateMeshRequest(b, 4), 12); },
       [](const Message& m) { EXPECT_EQ(m.body_as_MeshRequest()->model_id(), 4u); }},
      {Body::Mesh,
       [](FlatBufferBuilder& b) {
         const std::vector<std::uint32_t> indices = {0, 1, 2};
         const std::vector<float> uvs = {0, 0, 1, 0, 0, 1};
         const std::vector<float> positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
         const std::vector<std::uint16_t> joints(12, 0);
         const std::vector<float> weights = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
         return finish_message(
             b, CreateMeshDirect(b, 4, &indices, &uvs, &positions, &joints, &weights), 12);
       },
       [](const Message& m) {
         const Mesh* mesh = m.body_as_Mesh();
         EXPECT_EQ(mesh->model_id(), 4u);
         ASSERT_EQ(mesh->indices()->size(), 3u);
         EXPECT_EQ(mesh->indices()->Get(2), 2u);
         EXPECT_EQ(mesh->uvs()->Get(3), 0.0f);
         EXPECT_EQ(mesh->rest_positions()->Get(7), 1.0f);
         EXPECT_EQ(mesh->skin_joints()->size(), 12u);
         EXPECT_EQ(mesh->skin_weights()->Get(8), 1.0f);
       }},
      {Body::UploadClip,
       [](FlatBufferBuilder& b) {
         return finish_message(b, CreateUploadClipDirect(b, "walk.bvh", "HIERARCHY\n", 0.5f), 13);
       },
       [](const Message& m) {
         const UploadClip* upload = m.body_as_UploadClip();
         EXPECT_EQ(upload->bvh()->str(), "HIERARCHY\n");
         EXPECT_EQ(upload->length_scale(), 0.5f);
       }},
      {Body::ClipInfo,
       [](FlatBufferBuilder& b) {
         const auto warnings = b.CreateVectorOfStrings({"Frames: says 3, 2 rows"});
         return finish_message(b,
                               CreateClipInfo(b, b.CreateString(std::string(64, 'c')),
                                              b.CreateString("walk.bvh"), 2, 120.0f, 31, warnings),
                               13);
       },
       [](const Message& m) {
         const ClipInfo* info = m.body_as_ClipInfo();
         EXPECT_EQ(info->clip_id()->size(), 64u);
         EXPECT_EQ(info->frame_count(), 2u);
         EXPECT_EQ(info->frames_per_second(), 120.0f);
         EXPECT_EQ(info->warnings()->size(), 1u);
       }},
      {Body::PoseFromClip,
       [](FlatBufferBuilder& b) {
         PoseFields fields;
         fields.model_id = 4;
         fields.sequence = 9;
         const auto pose = add_pose(b, fields);
         const auto clip = CreateClipFrameDirect(b, "id", flatbuffers::nullopt, 1.5, true);
         return finish_message(b, CreatePoseFromClip(b, pose, clip), 14);
       },
       [](const Message& m) {
         const PoseFromClip* request = m.body_as_PoseFromClip();
         EXPECT_EQ(request->pose()->sequence(), 9u);
         EXPECT_FALSE(request->clip()->frame().has_value()) << "absent, not 0";
         EXPECT_EQ(request->clip()->time_seconds().value_or(0.0), 1.5);
         EXPECT_TRUE(request->clip()->loop());
       }},
      {Body::PoseByName,
       [](FlatBufferBuilder& b) {
         PoseFields fields;
         fields.model_id = 4;
         const auto pose = add_pose(b, fields);
         const Quat turn(0.0f, 0.0f, 0.6f, 0.8f);
         return finish_message(b,
                               CreatePoseByName(b, pose, b.CreateVectorOfStrings({"upperarm_l"}),
                                                b.CreateVectorOfStructs(&turn, 1)),
                               15);
       },
       [](const Message& m) {
         const PoseByName* request = m.body_as_PoseByName();
         EXPECT_EQ(request->joint_names()->Get(0)->str(), "upperarm_l");
         EXPECT_EQ(request->rotations()->Get(0)->z(), 0.6f);
       }},
      {Body::MapSharedMemory,
       [](FlatBufferBuilder& b) {
         return finish_message(b, CreateMapSharedMemory(b, 1703040), 16);
       },
       [](const Message& m) {
         EXPECT_EQ(m.body_as_MapSharedMemory()->bytes(), 1703040u);
         EXPECT_EQ(m.request_id(), 16u);
       }},
      {Body::SharedMemory,
       [](FlatBufferBuilder& b) { return finish_message(b, CreateSharedMemory(b, 1703040), 16); },
       [](const Message& m) { EXPECT_EQ(m.body_as_SharedMemory()->bytes(), 1703040u); }},
      {Body::ContactSheetRequest,
       [](FlatBufferBuilder& b) {
         const std::vector<std::uint32_t> frames = {197, 600};
         const std::vector<std::string> methods = {"sweep", "lbs"};
         return finish_message(
             b,
             CreateContactSheetRequest(b, 7, b.CreateString("c1"), b.CreateVector(frames),
                                       b.CreateVectorOfStrings(methods), 96, 128,
                                       b.CreateString("elbow_l"), true, 0.5f, 30.0f, 10.0f),
             17);
       },
       [](const Message& m) {
         const ContactSheetRequest* request = m.body_as_ContactSheetRequest();
         EXPECT_EQ(request->model_id(), 7u);
         EXPECT_EQ(request->frames()->Get(1), 600u);
         EXPECT_EQ(request->methods()->Get(1)->str(), "lbs");
         EXPECT_EQ(request->cell_height(), 128);
         EXPECT_EQ(request->focus()->str(), "elbow_l");
         EXPECT_EQ(request->elevation_degrees(), 10.0f);
       }},
      {Body::ContactSheet,
       [](FlatBufferBuilder& b) {
         const std::vector<std::uint8_t> png = {0x89, 'P', 'N', 'G'};
         const std::vector<float> stretch = {0.5f, 1.25f}, shortest = {0.5f, 0.9f},
                                  longest = {1.25f, 2.25f};
         return finish_message(
             b,
             CreateContactSheet(b, 7, 192, 128, b.CreateVector(png), b.CreateVector(stretch),
                                b.CreateString("gl"), b.CreateVector(shortest),
                                b.CreateVector(longest)),
             17);
       },
       [](const Message& m) {
         const ContactSheet* sheet = m.body_as_ContactSheet();
         EXPECT_EQ(sheet->width(), 192u);
         EXPECT_EQ(sheet->png()->size(), 4u);
         EXPECT_EQ(sheet->worst_stretch()->Get(1), 1.25f);
         EXPECT_EQ(sheet->renderer()->str(), "gl");
         EXPECT_EQ(sheet->shortest_edge_ratio()->Get(0), 0.5f);
         EXPECT_EQ(sheet->longest_edge_ratio()->Get(1), 2.25f);
       }},
      {Body::SubscribeStream,
       [](FlatBufferBuilder& b) {
         PoseFields fields;
         fields.method = DeformMethod::Dqs;
         fields.normals = true;
         const auto pose = add_pose(b, fields);
         return finish_message(b, CreateSubscribeStream(b, b.CreateString("mannequin"), pose), 18);
       },
       [](const Message& m) {
         const SubscribeStream* request = m.body_as_SubscribeStream();
         EXPECT_EQ(request->stream()->str(), "mannequin");
         EXPECT_EQ(request->pose()->method(), DeformMethod::Dqs);
         EXPECT_TRUE(request->pose()->normals());
       }},
      {Body::StreamSubscribed,
       [](FlatBufferBuilder& b) {
         return finish_message(b, CreateStreamSubscribed(b, b.CreateString("mannequin"), 7), 18);
       },
       [](const Message& m) {
         EXPECT_EQ(m.body_as_StreamSubscribed()->stream()->str(), "mannequin");
         EXPECT_EQ(m.body_as_StreamSubscribed()->model_id(), 7u);
         EXPECT_EQ(m.request_id(), 18u);
       }},
  };
}

TEST(Messages, SamplesCoverEveryBodyType) {
  const auto samples = one_of_each_body();
  ASSERT_EQ(samples.size(), static_cast<std::size_t>(Body::MAX));
  for (std::size_t i = 0; i < samples.size(); ++i) {
    EXPECT_EQ(samples[i].type, static_cast<Body>(i + 1)) << EnumNameBody(samples[i].type);
  }
}

TEST(Messages, EveryTypeSurvivesFramingThroughRandomChunks) {
  const auto samples = one_of_each_body();
  Bytes stream;
  std::vector<Bytes> sent;
  for (const Sample& sample : samples) {
    FlatBufferBuilder builder;
    sent.push_back(copy_of(sample.build(builder)));
    stream.insert(stream.end(), sent.back().begin(), sent.back().end());
  }
  // Several splits: chunk sizes from 1 byte (every boundary inside prefixes and bodies) up.
  for (unsigned seed = 1; seed <= 20; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937 random(seed);
    std::uniform_int_distribution<std::size_t> chunk(1, seed <= 5 ? 3 : 64 * seed);
    FrameReader reader;
    std::size_t received = 0;
    for (std::size_t at = 0; at < stream.size();) {
      const std::size_t size = std::min(chunk(random), stream.size() - at);
      std::span<const std::uint8_t> input(stream.data() + at, size);
      at += size;
      for (FrameEvent event = reader.read(input); event.status != FrameStatus::kPending;
           event = reader.read(input)) {
        ASSERT_EQ(event.status, FrameStatus::kFrame) << event.reason;
        ASSERT_LT(received, samples.size());
        EXPECT_EQ(copy_of(event.frame), sent[received]);  // byte for byte
        EXPECT_EQ(event.message->body_type(), samples[received].type);
        samples[received].check(*event.message);
        ++received;
      }
    }
    EXPECT_EQ(received, samples.size());
    EXPECT_FALSE(reader.mid_frame());
  }
}

TEST(Messages, BodyTypeFromANewerPeerVerifiesAndReadsAsUnknown) {
  // Additive evolution: a union member this build does not know passes verification, so
  // the server can answer UnknownMessage and go on.
  FlatBufferBuilder builder;
  const auto body = CreateByeDirect(builder, "from the future");
  const auto future_type = static_cast<Body>(static_cast<int>(Body::MAX) + 1);
  const Bytes frame =
      copy_of(finish_frame(builder, CreateMessage(builder, 5, future_type, body.Union())));
  FrameReader reader;
  const FrameEvent event = read_single(reader, frame);
  ASSERT_EQ(event.status, FrameStatus::kFrame) << event.reason;
  EXPECT_GT(event.message->body_type(), Body::MAX);
  EXPECT_EQ(event.message->request_id(), 5u);
}

PosedVerticesHeader header_for(std::uint32_t vertex_count, PositionFormat format) {
  return {.request_id = 12,
          .model_id = 1,
          .sequence = 40,
          .client_time_ns = 99,
          .vertex_count = vertex_count,
          .format = format,
          .normals = true};
}

TEST(PosedVerticesFrame, ArraysLieInsideTheFrameAndArriveBitForBit) {
  constexpr std::uint32_t kVertices = 20000;
  FlatBufferBuilder builder;
  PosedVerticesFrame frame(builder, header_for(kVertices, PositionFormat::Float32));
  ASSERT_EQ(frame.positions_f32().size(), 3 * kVertices);
  ASSERT_EQ(frame.normals_f32().size(), 3 * kVertices);
  EXPECT_TRUE(frame.positions_f16().empty());
  expect_inside_frame(frame.positions_f32().data(), frame.positions_f32().size_bytes(),
                      frame.bytes());
  expect_inside_frame(frame.normals_f32().data(), frame.normals_f32().size_bytes(), frame.bytes());
  std::mt19937 random(3);
  std::uniform_real_distribution<float> metres(-1.0f, 1.0f);
  std::vector<float> positions(3 * kVertices), normals(3 * kVertices);
  for (float& p : positions) p = metres(random);
  for (float& n : normals) n = metres(random);
  std::copy(positions.begin(), positions.end(), frame.positions_f32().begin());
  std::copy(normals.begin(), normals.end(), frame.normals_f32().begin());
  frame.timings().mutate_encode_ns(321);
  const Bytes sent = copy_of(frame.bytes());

  FrameReader reader;
  const FrameEvent event = read_single(reader, sent);
  ASSERT_EQ(event.status, FrameStatus::kFrame) << event.reason;
  EXPECT_EQ(event.message->request_id(), 12u);
  const PosedVertices* reply = event.message->body_as_PosedVertices();
  ASSERT_NE(reply, nullptr);
  EXPECT_EQ(reply->vertex_count(), kVertices);
  EXPECT_EQ(reply->client_time_ns(), 99u);
  EXPECT_EQ(reply->timings()->encode_ns(), 321u);
  std::vector<float> received_positions(3 * kVertices), received_normals(3 * kVertices);
  ASSERT_TRUE(copy_positions(*reply, received_positions));
  ASSERT_TRUE(copy_normals(*reply, received_normals));
  EXPECT_EQ(received_positions, positions);  // float32 travels exactly
  EXPECT_EQ(received_normals, normals);
}

TEST(PosedVerticesFrame, ReusesTheBuildersMemoryFrameAfterFrame) {
  // A server keeps one builder per connection: same-sized replies must not reallocate.
  FlatBufferBuilder builder(1 << 20);
  const std::uint8_t* first =
      PosedVerticesFrame(builder, header_for(5000, PositionFormat::Float32)).bytes().data();
  const std::uint8_t* second =
      PosedVerticesFrame(builder, header_for(5000, PositionFormat::Float32)).bytes().data();
  EXPECT_EQ(first, second);
}

TEST(PosedVerticesFrame, Float16RepliesDecodeWithinHalfAnUlp) {
  constexpr std::uint32_t kVertices = 1000;
  FlatBufferBuilder builder;
  PosedVerticesFrame frame(builder, header_for(kVertices, PositionFormat::Float16));
  ASSERT_EQ(frame.positions_f16().size(), 3 * kVertices);
  EXPECT_TRUE(frame.positions_f32().empty());
  std::vector<float> positions(3 * kVertices);
  for (std::size_t i = 0; i < positions.size(); ++i) positions[i] = 0.25f + 0.001f * i;
  encode_float16(positions, frame.positions_f16());
  encode_float16(positions, frame.normals_f16());
  const Bytes sent = copy_of(frame.bytes());
  FrameReader reader;
  const FrameEvent event = read_single(reader, sent);
  ASSERT_EQ(event.status, FrameStatus::kFrame) << event.reason;
  std::vector<float> received(3 * kVertices);
  ASSERT_TRUE(copy_positions(*event.message->body_as_PosedVertices(), received));
  for (std::size_t i = 0; i < positions.size(); ++i) {
    // Round to nearest binary16: at most half an ulp, 2^-11 relative (all values normal).
    EXPECT_LE(std::abs(received[i] - positions[i]), positions[i] * std::ldexp(1.0f, -11));
  }
}

TEST(PosedVerticesFrame, CopyRefusesAWrongSizedOutputOrMissingArrays) {
  FlatBufferBuilder builder;
  PosedVerticesHeader header = header_for(10, PositionFormat::Float32);
  header.normals = false;
  PosedVerticesFrame frame(builder, header);
  std::fill(frame.positions_f32().begin(), frame.positions_f32().end(), 1.0f);
  const auto* reply = GetSizePrefixedMessage(frame.bytes().data())->body_as_PosedVertices();
  std::vector<float> out(29, -7.0f);
  EXPECT_FALSE(copy_positions(*reply, out));
  EXPECT_EQ(out[0], -7.0f);  // untouched
  out.resize(30);
  EXPECT_FALSE(copy_normals(*reply, out));
  EXPECT_TRUE(copy_positions(*reply, out));
  EXPECT_EQ(out[29], 1.0f);
}

// 1.10: a pose that asks for its reply in shared memory says where; the reply carries no arrays,
// only that offset — a frame of a few dozen bytes whatever the vertex count.
TEST(PosedVerticesFrame, SharedMemoryPosesAndRepliesCarryTheOffsetAndNoArrays) {
  FlatBufferBuilder builder;
  PoseFields fields;
  fields.model_id = 3;
  fields.shared_offset = 851520;
  const Pose* pose =
      GetSizePrefixedMessage(finish_message(builder, add_pose(builder, fields)).data())
          ->body_as_Pose();
  EXPECT_TRUE(pose->into_shared_memory());
  EXPECT_EQ(pose->shared_offset(), 851520u);
  fields.shared_offset = std::nullopt;
  pose = GetSizePrefixedMessage(finish_message(builder, add_pose(builder, fields)).data())
             ->body_as_Pose();
  EXPECT_FALSE(pose->into_shared_memory());

  PosedVerticesHeader header = header_for(70000, PositionFormat::Float32);
  header.shared_offset = 851520;
  const PosedVerticesFrame frame(builder, header);
  EXPECT_TRUE(frame.positions_f32().empty());
  EXPECT_TRUE(frame.normals_f32().empty());
  EXPECT_LT(frame.bytes().size(), 200u);
  const PosedVertices* reply =
      GetSizePrefixedMessage(frame.bytes().data())->body_as_PosedVertices();
  EXPECT_TRUE(reply->in_shared_memory());
  EXPECT_EQ(reply->shared_offset(), 851520u);
  EXPECT_EQ(reply->vertex_count(), 70000u);
  EXPECT_EQ(reply->positions_f32(), nullptr);
  std::vector<float> out(3 * 70000);
  EXPECT_FALSE(copy_positions(*reply, out)) << "the vertices are not in the frame";
}

TEST(PositionMapFrame, ExrBytesWrittenInPlaceArriveIntact) {
  FlatBufferBuilder builder;
  PositionMapFrame frame(builder, {.request_id = 8,
                                   .model_id = 2,
                                   .sequence = 77,
                                   .width = 512,
                                   .height = 256,
                                   .exr_bytes = 4099});
  ASSERT_EQ(frame.exr().size(), 4099u);
  expect_inside_frame(frame.exr().data(), frame.exr().size(), frame.bytes());
  for (std::size_t i = 0; i < frame.exr().size(); ++i) {
    frame.exr()[i] = static_cast<std::uint8_t>(i * 7);
  }
  frame.timings().mutate_deform_ns(55);
  const Bytes sent = copy_of(frame.bytes());
  FrameReader reader;
  const FrameEvent event = read_single(reader, sent);
  ASSERT_EQ(event.status, FrameStatus::kFrame) << event.reason;
  const PositionMap* map = event.message->body_as_PositionMap();
  ASSERT_NE(map, nullptr);
  EXPECT_EQ(map->sequence(), 77u);
  EXPECT_EQ(map->width(), 512u);
  EXPECT_EQ(map->timings()->deform_ns(), 55u);
  ASSERT_EQ(map->exr()->size(), 4099u);
  int wrong = 0;
  for (flatbuffers::uoffset_t i = 0; i < map->exr()->size(); ++i) {
    if (map->exr()->Get(i) != static_cast<std::uint8_t>(i * 7)) ++wrong;
  }
  EXPECT_EQ(wrong, 0);
}

// A Pose table read back from its own frame, for check_pose_enums.
class PoseCheck : public ::testing::Test {
 protected:
  const Pose& pose(const PoseFields& fields) {
    builder_.Clear();
    finish_message(builder_, add_pose(builder_, fields));
    return *GetSizePrefixedMessage(builder_.GetBufferPointer())->body_as_Pose();
  }
  FlatBufferBuilder builder_;
};

TEST_F(PoseCheck, KnownEnumsPassWhateverTheRotations) {
  EXPECT_EQ(check_pose_enums(pose(three_joint_pose())), std::nullopt);
  // The rotations are the deformation job's to check (against the model), not the wire's.
  std::vector<Quat> rotations = kRotations;
  rotations[1] = Quat(std::numeric_limits<float>::quiet_NaN(), 0, 0, 2);
  PoseFields fields = three_joint_pose();
  fields.rotations = rotations;
  EXPECT_EQ(check_pose_enums(pose(fields)), std::nullopt);
}

TEST_F(PoseCheck, UnknownMethodFeatureOrFormatFromANewerClientIsNotAvailable) {
  PoseFields fields = three_joint_pose();
  fields.method = static_cast<DeformMethod>(9);
  auto problem = check_pose_enums(pose(fields));
  ASSERT_TRUE(problem);
  EXPECT_EQ(problem->code, ErrorCode::NotAvailable);
  EXPECT_NE(problem->message.find("pose 1001"), std::string::npos) << problem->message;
  EXPECT_NE(problem->message.find("method 9"), std::string::npos) << problem->message;

  fields = three_joint_pose();
  fields.features = static_cast<Features>(1u << 7);
  problem = check_pose_enums(pose(fields));
  ASSERT_TRUE(problem);
  EXPECT_EQ(problem->code, ErrorCode::NotAvailable);
  EXPECT_NE(problem->message.find("feature flags 128"), std::string::npos) << problem->message;

  fields = three_joint_pose();
  fields.positions = static_cast<PositionFormat>(7);
  problem = check_pose_enums(pose(fields));
  ASSERT_TRUE(problem);
  EXPECT_EQ(problem->code, ErrorCode::NotAvailable);
  EXPECT_NE(problem->message.find("position format 7"), std::string::npos) << problem->message;
}

}  // namespace
}  // namespace sweepd::protocol
