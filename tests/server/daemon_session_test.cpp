// sweepd as a client meets it: the real daemon on an ephemeral localhost port, real sockets.
// Hello and the token, ListModels, ModelInfo, and poses whose vertices must equal the
// library's own DeformJob output for the same bound model bit for bit.
#include <gtest/gtest.h>

#include <cstring>

#include "io/sweepbind/sweepbind.h"
#include "protocol/float16.h"
#include "tests/server/daemon_process.h"
#include "tests/server/pose_frames.h"
#include "tests/server/stored_binding.h"

namespace sweepd::test::daemon_session_test {
namespace {

constexpr char kToken[] = "s3cret-token";

class DaemonSession : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    directory_ = new fs::path(fresh_directory("session"));
    // 45,000 vertices: an idle daemon with more than one core splits such a pose over threads
    // (--deform-threads 0, the default: server/services/spare_cores.h), so the bit-for-bit
    // comparisons below cover the split path too.
    daemon_ = new DaemonProcess(*directory_, {"--token", kToken, "--unix-socket",
                                              (*directory_ / "sweepd.sock").string(),
                                              "--mannequin-vertices", "45000"});
  }
  static void TearDownTestSuite() {
    delete daemon_;
    fs::remove_all(*directory_);
    delete directory_;
  }
  void SetUp() override { ASSERT_TRUE(daemon_->running()) << daemon_->log(); }

  // The mannequin exactly as the daemon holds it: its stored binding, read back.
  static const deform::BoundModel& stored_mannequin() {
    static const deform::BoundModel bound =
        io::load_sweepbind(stored_binding(*directory_ / "store", "mannequin"));
    return bound;
  }

  static fs::path* directory_;
  static DaemonProcess* daemon_;
};
fs::path* DaemonSession::directory_ = nullptr;
DaemonProcess* DaemonSession::daemon_ = nullptr;

TEST_F(DaemonSession, RightTokenIsWelcomedWithLimitsAndCapabilities) {
  FrameClient client(daemon_->port());
  ASSERT_TRUE(client.connected());
  const protocol::Welcome* welcome = client.hello(kToken);
  ASSERT_NE(welcome, nullptr);
  EXPECT_EQ(welcome->version_major(), protocol::kProtocolVersionMajor);
  EXPECT_EQ(welcome->max_frame_bytes(), protocol::kDefaultMaxFrameBytes);  // the default
  EXPECT_EQ(welcome->max_poses_in_flight(), 8u);                           // the default
  std::vector<std::string> capabilities;
  for (const auto* c : *welcome->capabilities()) capabilities.push_back(c->str());
  EXPECT_NE(std::find(capabilities.begin(), capabilities.end(), "sweep"), capabilities.end());
  // Position maps are on by default (EGL: a GPU or llvmpipe).
  EXPECT_NE(std::find(capabilities.begin(), capabilities.end(), "position_map"),
            capabilities.end());
}

TEST_F(DaemonSession, WrongTokenIsRefusedAndTheConnectionClosed) {
  FrameClient client(daemon_->port());
  flatbuffers::FlatBufferBuilder builder;
  client.send_bytes(protocol::build_hello(builder, "s3cret-tokeN", "intruder",
                                          protocol::PoseDelivery::InOrder, 5));
  const protocol::Message* reply = client.receive();
  ASSERT_NE(reply, nullptr);
  EXPECT_EQ(reply->request_id(), 5u);
  const protocol::Error* error = reply->body_as_Error();
  ASSERT_NE(error, nullptr);
  EXPECT_EQ(error->code(), protocol::ErrorCode::AuthFailed);
  EXPECT_TRUE(error->fatal());
  EXPECT_TRUE(client.closed_by_server());
}

TEST_F(DaemonSession, AnyMessageBeforeHelloIsNotAuthenticated) {
  FrameClient client(daemon_->port());
  flatbuffers::FlatBufferBuilder builder;
  client.send_bytes(
      protocol::finish_message(builder, protocol::CreateListModels(builder), /*request_id=*/9));
  const protocol::Error* error = client.receive_as<protocol::Error>();
  ASSERT_NE(error, nullptr);
  EXPECT_EQ(error->code(), protocol::ErrorCode::NotAuthenticated);
  EXPECT_TRUE(client.closed_by_server());
}

TEST_F(DaemonSession, ListModelsNamesTheDefaultMannequinWithItsCounts) {
  FrameClient client(daemon_->port());
  ASSERT_NE(client.hello(kToken), nullptr);
  flatbuffers::FlatBufferBuilder builder;
  client.send_bytes(protocol::finish_message(builder, protocol::CreateListModels(builder), 2));
  const protocol::ModelList* list = client.receive_as<protocol::ModelList>();
  ASSERT_NE(list, nullptr);
  ASSERT_EQ(list->models()->size(), 1u);
  const protocol::ModelSummary* mannequin = list->models()->Get(0);
  EXPECT_EQ(mannequin->model_id(), daemon_->model_id());
  EXPECT_EQ(mannequin->name()->str(), "mannequin");
  // The handle is the content id's first 8 hex digits (server/models/content_id.h).
  ASSERT_NE(mannequin->content_id(), nullptr);
  ASSERT_EQ(mannequin->content_id()->size(), 64u);
  EXPECT_EQ(mannequin->model_id(),
            std::stoul(mannequin->content_id()->str().substr(0, 8), nullptr, 16));
  EXPECT_EQ(mannequin->vertex_count(), stored_mannequin().model.vertex_count());
  EXPECT_EQ(mannequin->joint_count(), stored_mannequin().model.skeleton.joints.size());
}

TEST_F(DaemonSession, LoadModelByNameAnswersModelInfoWithJointOrder) {
  FrameClient client(daemon_->port());
  ASSERT_NE(client.hello(kToken), nullptr);
  flatbuffers::FlatBufferBuilder builder;
  client.send_bytes(
      protocol::finish_message(builder, protocol::CreateLoadModelDirect(builder, "mannequin"), 3));
  const protocol::ModelInfo* info = client.receive_as<protocol::ModelInfo>();
  ASSERT_NE(info, nullptr);
  const deform::Skeleton& skeleton = stored_mannequin().model.skeleton;
  EXPECT_EQ(info->model_id(), daemon_->model_id());
  ASSERT_EQ(info->joint_names()->size(), skeleton.joints.size());
  for (std::size_t j = 0; j < skeleton.joints.size(); ++j) {
    EXPECT_EQ(info->joint_names()->Get(j)->str(), skeleton.joints[j].name);
    EXPECT_EQ(info->joint_parents()->Get(j), skeleton.joints[j].parent);
  }
  EXPECT_EQ(info->bind()->sweep_count(), stored_mannequin().sweeps.size());
  EXPECT_GT(info->bind()->swept_vertex_count(), info->bind()->skinned_vertex_count());
}

// Bit-exact: the server must hand back exactly the library's float32 results.
void expect_bitwise_equal(std::span<const float> served, const std::vector<glm::vec3>& library,
                          const char* what) {
  ASSERT_EQ(served.size(), 3 * library.size()) << what;
  EXPECT_EQ(std::memcmp(served.data(), library.data(), served.size() * sizeof(float)), 0)
      << what << " differ from the library's DeformJob output";
}

std::span<const float> floats(const flatbuffers::Vector<float>* vector) {
  return vector ? std::span<const float>(vector->data(), vector->size()) : std::span<const float>();
}

TEST_F(DaemonSession, PosedVerticesEqualTheLibrarysDeformJobBitForBitForEveryMethod) {
  const deform::BoundModel& bound = stored_mannequin();
  const std::vector<glm::quat> rotations = bent_rotations(bound.model.skeleton.joints.size());
  const std::vector<protocol::Quat> wire = to_wire(rotations);
  FrameClient client(daemon_->port());
  ASSERT_NE(client.hello(kToken), nullptr);
  const std::pair<protocol::DeformMethod, deform::DeformMethod> methods[] = {
      {protocol::DeformMethod::Sweep, deform::DeformMethod::kSweep},
      {protocol::DeformMethod::Lbs, deform::DeformMethod::kLbs},
      {protocol::DeformMethod::Dqs, deform::DeformMethod::kDqs}};
  std::uint64_t sequence = 0;
  for (const auto& [wire_method, library_method] : methods) {
    ++sequence;
    protocol::PoseFields fields = pose_fields(daemon_->model_id(), sequence, wire);
    fields.client_time_ns = 77;
    fields.method = wire_method;
    fields.normals = true;
    ASSERT_TRUE(send_pose(client, fields, 100 + sequence));
    const protocol::PosedVertices* reply = client.receive_as<protocol::PosedVertices>();
    ASSERT_NE(reply, nullptr);
    EXPECT_EQ(reply->sequence(), sequence);
    EXPECT_EQ(reply->client_time_ns(), 77u);
    EXPECT_EQ(reply->vertex_count(), bound.model.vertex_count());
    const Deformed library = library_deformation(bound, rotations, library_method);
    expect_bitwise_equal(floats(reply->positions_f32()), library.positions,
                         deform::to_string(library_method));
    expect_bitwise_equal(floats(reply->normals_f32()), library.normals,
                         deform::to_string(library_method));
    // The pose must actually move the mesh: otherwise equality would prove little.
    float largest_move = 0.0f;
    for (std::size_t v = 0; v < library.positions.size(); ++v) {
      largest_move =
          std::max(largest_move, glm::length(library.positions[v] - bound.model.positions[v]));
    }
    EXPECT_GT(largest_move, 0.05f) << "bent pose moves some vertex by at least 5 cm";
  }
}

TEST_F(DaemonSession, Float16RepliesAreTheLibraryOutputRoundedToHalf) {
  const deform::BoundModel& bound = stored_mannequin();
  const std::vector<glm::quat> rotations = bent_rotations(bound.model.skeleton.joints.size(), 1.5f);
  const std::vector<protocol::Quat> wire = to_wire(rotations);
  FrameClient client(daemon_->port());
  ASSERT_NE(client.hello(kToken), nullptr);
  protocol::PoseFields fields = pose_fields(daemon_->model_id(), 1, wire);
  fields.positions = protocol::PositionFormat::Float16;
  ASSERT_TRUE(send_pose(client, fields));
  const protocol::PosedVertices* reply = client.receive_as<protocol::PosedVertices>();
  ASSERT_NE(reply, nullptr);
  ASSERT_EQ(reply->positions_f32(), nullptr);
  ASSERT_NE(reply->positions_f16(), nullptr);
  const Deformed library = library_deformation(bound, rotations, deform::DeformMethod::kSweep);
  std::vector<std::uint16_t> expected(3 * library.positions.size());
  protocol::encode_float16({&library.positions[0].x, expected.size()}, expected);
  ASSERT_EQ(reply->positions_f16()->size(), expected.size());
  // Exact: the server encodes the same float32 values with the same rounding.
  EXPECT_EQ(std::memcmp(reply->positions_f16()->data(), expected.data(), expected.size() * 2), 0);
}

TEST_F(DaemonSession, UnixSocketServesTheSameSession) {
  FrameClient client(*directory_ / "sweepd.sock");
  ASSERT_TRUE(client.connected());
  ASSERT_NE(client.hello(kToken), nullptr);
  const deform::BoundModel& bound = stored_mannequin();
  const std::vector<glm::quat> rotations = bent_rotations(bound.model.skeleton.joints.size());
  const std::vector<protocol::Quat> wire = to_wire(rotations);
  ASSERT_TRUE(send_pose(client, pose_fields(daemon_->model_id(), 4, wire)));
  const protocol::PosedVertices* reply = client.receive_as<protocol::PosedVertices>();
  ASSERT_NE(reply, nullptr);
  expect_bitwise_equal(
      floats(reply->positions_f32()),
      library_deformation(bound, rotations, deform::DeformMethod::kSweep).positions,
      "positions over the Unix socket");
}

TEST_F(DaemonSession, StatsCountThisConnectionsPoses) {
  FrameClient client(daemon_->port());
  const protocol::Welcome* welcome = client.hello(kToken);
  ASSERT_NE(welcome, nullptr);
  const std::uint64_t connection_id = welcome->connection_id();
  const std::vector<protocol::Quat> wire =
      to_wire(bent_rotations(stored_mannequin().model.skeleton.joints.size()));
  for (std::uint64_t s = 1; s <= 3; ++s) {
    ASSERT_TRUE(send_pose(client, pose_fields(daemon_->model_id(), s, wire)));
    ASSERT_NE(client.receive_as<protocol::PosedVertices>(), nullptr);
  }
  flatbuffers::FlatBufferBuilder builder;
  client.send_bytes(protocol::finish_message(builder, protocol::CreateStatsRequest(builder), 8));
  const protocol::Stats* stats = client.receive_as<protocol::Stats>();
  ASSERT_NE(stats, nullptr);
  const protocol::ConnectionStats* mine = nullptr;
  for (const protocol::ConnectionStats* c : *stats->connections()) {
    if (c->connection_id() == connection_id) mine = c;
  }
  ASSERT_NE(mine, nullptr);
  EXPECT_EQ(mine->poses_received(), 3u);
  EXPECT_EQ(mine->poses_answered(), 3u);
  EXPECT_EQ(mine->client_name()->str(), "server_test");
  EXPECT_GT(mine->server_latency()->p50_ns(), 0u);
  EXPECT_LE(mine->server_latency()->p50_ns(), mine->server_latency()->max_ns());
  ASSERT_GE(stats->models()->size(), 1u);
  const protocol::ModelStats* mannequin = stats->models()->Get(0);
  EXPECT_EQ(mannequin->name()->str(), "mannequin");
  EXPECT_GE(mannequin->poses(), 3u);  // other tests of this process may have posed it too
  EXPECT_GT(mannequin->deform_latency()->p50_ns(), 0u);
  EXPECT_LE(mannequin->deform_latency()->p99_ns(), mannequin->deform_latency()->max_ns());
}

}  // namespace
}  // namespace sweepd::test::daemon_session_test
