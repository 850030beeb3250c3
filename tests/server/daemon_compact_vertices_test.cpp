// Compact vertex streams through the real daemon (protocol 1.5, issue 18 item 6): the same pose
// of the 72k mannequin and of the shared 14.5k MakeHuman male answered as float32, float16 and
// meshopt, each decoded by protocol::copy_positions / copy_normals (what the C++ client
// calls) and compared with the float32 reply; bytes per pose measured on the frames; unknown
// formats refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "tests/server/daemon_process.h"
#include "tests/server/pose_frames.h"

namespace sweepd::test::daemon_compact_vertices_test {
namespace {

namespace pb = sweepd::protocol;

constexpr char kToken[] = "compact";

class DaemonCompactVertices : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    directory_ = new fs::path(fresh_directory("compact_vertices"));
    // The mannequin at about 72k vertices (the paper's scale) is what the issue measures.
    daemon_ = new DaemonProcess(
        *directory_, {"--token", kToken, "--position-maps", "0", "--mannequin-vertices", "72000"});
  }
  static void TearDownTestSuite() {
    delete daemon_;
    fs::remove_all(*directory_);
    delete directory_;
  }
  void SetUp() override {
    ASSERT_TRUE(daemon_->running()) << daemon_->log();
    client_ = std::make_unique<FrameClient>(daemon_->port());
    ASSERT_NE(client_->hello(kToken), nullptr);
  }

  // The shared male uploaded; 0 when the shared data is absent.
  std::uint32_t upload_male() {
    const fs::path male = fs::path(SWEEPD_SHARED_DATA) / "models/makehuman_male_cmu.glb";
    if (!fs::exists(male)) return 0;
    const std::vector<std::uint8_t> glb = read_bytes(male);
    flatbuffers::FlatBufferBuilder builder;
    client_->send_bytes(
        pb::finish_message(builder, pb::CreateLoadModelDirect(builder, "male", &glb), 2));
    const pb::ModelInfo* info = client_->receive_as<pb::ModelInfo>();
    return info == nullptr ? 0 : info->model_id();
  }

  std::uint32_t joint_count(std::uint32_t model_id) {
    flatbuffers::FlatBufferBuilder builder;
    client_->send_bytes(pb::finish_message(builder, pb::CreateListModels(builder), 3));
    const pb::ModelList* list = client_->receive_as<pb::ModelList>();
    if (list == nullptr) return 0;
    for (const pb::ModelSummary* model : *list->models())
      if (model->model_id() == model_id) return model->joint_count();
    return 0;
  }

  struct Reply {
    std::vector<float> positions, normals;
    std::size_t frame_bytes = 0;  // the whole frame, length prefix included
  };

  // One pose in `format`, decoded to float32 as the C++ client decodes it.
  Reply pose(std::uint32_t model_id, pb::PositionFormat format, bool normals) {
    const std::vector<glm::quat> rotations = bent_rotations(joint_count(model_id), 0.7f);
    const std::vector<pb::Quat> wire = to_wire(rotations);
    pb::PoseFields fields = pose_fields(model_id, 1, wire);
    fields.positions = format;
    fields.normals = normals;
    Reply reply;
    if (!send_pose(*client_, fields)) return reply;
    const pb::PosedVertices* posed = client_->receive_as<pb::PosedVertices>();
    if (posed == nullptr) return reply;
    reply.frame_bytes = client_->last_frame().size();
    const std::size_t values = 3 * std::size_t{posed->vertex_count()};
    reply.positions.resize(values);
    if (!pb::copy_positions(*posed, reply.positions)) reply.positions.clear();
    if (normals) {
      reply.normals.resize(values);
      if (!pb::copy_normals(*posed, reply.normals)) reply.normals.clear();
    }
    return reply;
  }

  // Float32, float16 and meshopt replies of one pose: errors against float32, and bytes per
  // pose (positions only) at least `fewer_bytes` times fewer than float32's.
  void expect_compact_within_a_tenth_of_a_millimetre(std::uint32_t model_id,
                                                     const std::string& name, double fewer_bytes) {
    const Reply exact = pose(model_id, pb::PositionFormat::Float32, true);
    const Reply half = pose(model_id, pb::PositionFormat::Float16, true);
    const Reply meshopt = pose(model_id, pb::PositionFormat::Meshopt, true);
    ASSERT_FALSE(exact.positions.empty()) << daemon_->log();
    ASSERT_EQ(half.positions.size(), exact.positions.size()) << name;
    ASSERT_EQ(meshopt.positions.size(), exact.positions.size()) << name;
    ASSERT_EQ(meshopt.normals.size(), exact.normals.size()) << name;
    auto largest = [](const std::vector<float>& a, const std::vector<float>& b) {
      float worst = 0.0f;
      for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(a[i] - b[i]));
      return worst;
    };
    // The target is 0.1 mm; the 0.18 mm grid rounds to half a step (0.09 mm), plus
    // float32 rounding of origin + step * q (under 1 µm on a 2 m body).
    EXPECT_LE(largest(meshopt.positions, exact.positions), 0.5f * pb::kMeshoptPositionStep + 1e-6f)
        << name;
    // int8 normals: half of 1/127 per component, plus float rounding.
    EXPECT_LE(largest(meshopt.normals, exact.normals), 0.5f / 127.0f + 1e-6f) << name;
    // float16: 2^-11 relative, under 1 mm within 2 m of the origin.
    EXPECT_LE(largest(half.positions, exact.positions), 1e-3f) << name;

    // Bytes per pose, positions only (the target: 3× fewer than float32).
    const Reply exact_positions = pose(model_id, pb::PositionFormat::Float32, false);
    const Reply meshopt_positions = pose(model_id, pb::PositionFormat::Meshopt, false);
    const double ratio = static_cast<double>(exact_positions.frame_bytes) /
                         static_cast<double>(meshopt_positions.frame_bytes);
    std::printf(
        "%s, %zu vertices: bytes per pose, positions only: float32 %zu, meshopt %zu (%.2fx); "
        "with normals: float32 %zu, float16 %zu, meshopt %zu (%.2fx); meshopt error %.4f mm\n",
        name.c_str(), exact.positions.size() / 3, exact_positions.frame_bytes,
        meshopt_positions.frame_bytes, ratio, exact.frame_bytes, half.frame_bytes,
        meshopt.frame_bytes, static_cast<double>(exact.frame_bytes) / meshopt.frame_bytes,
        1e3 * largest(meshopt.positions, exact.positions));
    EXPECT_GE(ratio, fewer_bytes) << name;
    EXPECT_LT(meshopt.frame_bytes, half.frame_bytes) << name;
  }

  static fs::path* directory_;
  static DaemonProcess* daemon_;
  std::unique_ptr<FrameClient> client_;
};
fs::path* DaemonCompactVertices::directory_ = nullptr;
DaemonProcess* DaemonCompactVertices::daemon_ = nullptr;

TEST_F(DaemonCompactVertices, WelcomeAdvertisesMeshopt) {
  FrameClient client(daemon_->port());
  const pb::Welcome* welcome = client.hello(kToken);
  ASSERT_NE(welcome, nullptr);
  EXPECT_EQ(welcome->version_minor(), pb::kProtocolVersionMinor);
  const auto* capabilities = welcome->capabilities();
  EXPECT_TRUE(std::any_of(capabilities->begin(), capabilities->end(),
                          [](const auto* c) { return c->str() == "meshopt"; }));
}

TEST_F(DaemonCompactVertices, MannequinRoundTripsEveryEncodingWithinATenthOfAMillimetre) {
  // 3.45× measured (bench/vertex_stream_bench.cpp): the mannequin's vertices follow its
  // surface (mannequin.cpp), so the codec's deltas between consecutive vertices stay small.
  // The 3× must hold.
  expect_compact_within_a_tenth_of_a_millimetre(daemon_->model_id(), "mannequin", 3.0);
}

TEST_F(DaemonCompactVertices, SharedMaleRoundTripsEveryEncodingWithinATenthOfAMillimetre) {
  const std::uint32_t male = upload_male();
  if (male == 0) GTEST_SKIP() << "shared data absent: " << SWEEPD_SHARED_DATA;
  // 3.16–3.17× measured: the 3× holds.
  expect_compact_within_a_tenth_of_a_millimetre(male, "male", 3.0);
}

TEST_F(DaemonCompactVertices, AnUnknownFormatIsNotAvailableAndTheSessionGoesOn) {
  const std::vector<pb::Quat> wire = to_wire(bent_rotations(joint_count(daemon_->model_id())));
  pb::PoseFields fields = pose_fields(daemon_->model_id(), 42, wire);
  fields.positions = static_cast<pb::PositionFormat>(3);  // a format of a newer client
  ASSERT_TRUE(send_pose(*client_, fields, 9));
  const pb::Message* message = client_->receive();
  ASSERT_NE(message, nullptr);
  EXPECT_EQ(message->request_id(), 9u);
  const pb::Error* error = message->body_as_Error();
  ASSERT_NE(error, nullptr);
  EXPECT_EQ(error->code(), pb::ErrorCode::NotAvailable);
  EXPECT_EQ(error->sequence(), 42u);
  EXPECT_NE(error->message()->str().find("unknown position format 3"), std::string::npos)
      << error->message()->str();
  EXPECT_FALSE(error->fatal());
  EXPECT_FALSE(pose(daemon_->model_id(), pb::PositionFormat::Meshopt, false).positions.empty());
}

}  // namespace
}  // namespace sweepd::test::daemon_compact_vertices_test
