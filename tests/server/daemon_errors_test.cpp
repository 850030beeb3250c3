// sweepd under bad input: every broken frame or request gets a typed Error on its own
// connection, the connection keeps being served, and a second client never notices.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "tests/server/daemon_process.h"
#include "tests/server/pose_frames.h"

namespace sweepd::test {
namespace {

constexpr std::uint32_t kMaxFrameBytes = 64 * 1024;
constexpr std::uint32_t kMannequinJoints = 31;  // mannequin/mannequin.h: 31 joints

class DaemonErrors : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    directory_ = new fs::path(fresh_directory("errors"));
    daemon_ = new DaemonProcess(
        *directory_, {"--max-frame-bytes", std::to_string(kMaxFrameBytes), "--max-connections", "3",
                      "--position-maps", "0", "--hello-timeout-ms", "300"});
  }
  static void TearDownTestSuite() {
    delete daemon_;
    fs::remove_all(*directory_);
    delete directory_;
  }
  void SetUp() override {
    ASSERT_TRUE(daemon_->running());
    broken_ = std::make_unique<FrameClient>(daemon_->port());
    healthy_ = std::make_unique<FrameClient>(daemon_->port());
    ASSERT_NE(broken_->hello(""), nullptr);
    ASSERT_NE(healthy_->hello(""), nullptr);
  }

  // The error `broken_` gets next; then both clients must still be answered.
  void expect_error_then_service(protocol::ErrorCode code, const std::string& message_part,
                                 std::uint64_t sequence = 0) {
    const protocol::Error* error = broken_->receive_as<protocol::Error>();
    ASSERT_NE(error, nullptr);
    EXPECT_EQ(error->code(), code) << error->message()->str();
    EXPECT_FALSE(error->fatal());
    EXPECT_NE(error->message()->str().find(message_part), std::string::npos)
        << error->message()->str();
    EXPECT_EQ(error->sequence(), sequence);
    for (FrameClient* client : {healthy_.get(), broken_.get()}) {
      ASSERT_TRUE(
          send_pose(*client, pose_fields(daemon_->model_id(), 1000 + ++poses_, rotations_)));
      const protocol::PosedVertices* reply = client->receive_as<protocol::PosedVertices>();
      ASSERT_NE(reply, nullptr);
      EXPECT_EQ(reply->sequence(), 1000 + poses_);
    }
  }

  static fs::path* directory_;
  static DaemonProcess* daemon_;
  std::unique_ptr<FrameClient> broken_, healthy_;
  std::vector<protocol::Quat> rotations_ = to_wire(bent_rotations(kMannequinJoints));
  std::uint64_t poses_ = 0;
};
fs::path* DaemonErrors::directory_ = nullptr;
DaemonProcess* DaemonErrors::daemon_ = nullptr;

std::vector<std::uint8_t> frame_with_body(std::vector<std::uint8_t> body) {
  const auto length = static_cast<std::uint32_t>(body.size());
  std::vector<std::uint8_t> frame(4 + body.size());
  for (std::size_t i = 0; i < 4; ++i) frame[i] = static_cast<std::uint8_t>(length >> (8 * i));
  std::copy(body.begin(), body.end(), frame.begin() + 4);
  return frame;
}

TEST_F(DaemonErrors, FrameTooShortForAFlatBufferIsABadFrame) {
  ASSERT_TRUE(broken_->send_bytes(frame_with_body({1, 2, 3, 4})));
  expect_error_then_service(protocol::ErrorCode::BadFrame, "4");
}

TEST_F(DaemonErrors, GarbageThatFailsVerificationIsABadFrame) {
  std::vector<std::uint8_t> body(64, 0xEE);
  std::memcpy(body.data() + 4, "SWPD", 4);  // right identifier, root offset far out of range
  ASSERT_TRUE(broken_->send_bytes(frame_with_body(body)));
  expect_error_then_service(protocol::ErrorCode::BadFrame, "");
}

TEST_F(DaemonErrors, ABodyTypeWithoutItsBodyIsABadFrame) {
  // FlatBuffers' verifier accepts a union whose type is set and whose value is absent; the
  // daemon dereferenced the absent body and died (found by the frames fuzzer). Every body type
  // a client may send is tried; the connection and the server go on.
  for (const protocol::Body type :
       {protocol::Body::Pose, protocol::Body::LoadModel, protocol::Body::PositionMapRequest,
        protocol::Body::MeshRequest, protocol::Body::EditKeyEllipse, protocol::Body::ListModels,
        protocol::Body::Bye, protocol::Body::Hello}) {
    SCOPED_TRACE(protocol::EnumNameBody(type));
    flatbuffers::FlatBufferBuilder builder;
    const std::span<const std::uint8_t> frame =
        protocol::finish_frame(builder, protocol::CreateMessage(builder, 0, type, 0));
    ASSERT_TRUE(broken_->send_bytes({frame.begin(), frame.end()}));
    expect_error_then_service(
        protocol::ErrorCode::BadFrame,
        std::string("says its body is a ") + protocol::EnumNameBody(type) + " but carries none");
  }
}

TEST_F(DaemonErrors, WrongIdentifierIsNamed) {
  flatbuffers::FlatBufferBuilder builder;
  protocol::finish_message(builder, protocol::CreateListModels(builder));
  std::vector<std::uint8_t> frame(builder.GetBufferPointer(),
                                  builder.GetBufferPointer() + builder.GetSize());
  frame.at(8) = 'X';  // "SWPD" becomes "XWPD"
  ASSERT_TRUE(broken_->send_bytes(frame));
  expect_error_then_service(protocol::ErrorCode::WrongIdentifier, "XWPD");
}

TEST_F(DaemonErrors, OversizedFrameIsRefusedAndItsBodySkipped) {
  // Over the limit: the server answers at once and discards the declared bytes unread.
  const std::uint32_t declared = 4 * kMaxFrameBytes;
  std::vector<std::uint8_t> frame(4 + declared, 0x5A);
  std::memcpy(frame.data(), &declared, 4);
  ASSERT_TRUE(broken_->send_bytes(frame));
  expect_error_then_service(protocol::ErrorCode::FrameTooLarge, std::to_string(declared));
}

TEST_F(DaemonErrors, WrongJointCountNamesThePoseAndBothCounts) {
  const std::span<const protocol::Quat> short_pose(rotations_.data(), kMannequinJoints - 1);
  ASSERT_TRUE(send_pose(*broken_, pose_fields(daemon_->model_id(), 42, short_pose)));
  expect_error_then_service(protocol::ErrorCode::WrongJointCount, "30 rotations", 42);
}

TEST_F(DaemonErrors, NaNRotationIsAnInvalidPose) {
  std::vector<protocol::Quat> nan_pose = rotations_;
  nan_pose[7] = protocol::Quat(std::numeric_limits<float>::quiet_NaN(), 0, 0, 1);
  ASSERT_TRUE(send_pose(*broken_, pose_fields(daemon_->model_id(), 43, nan_pose)));
  expect_error_then_service(protocol::ErrorCode::InvalidPose, "joint 7", 43);
}

TEST_F(DaemonErrors, RotationFarFromUnitLengthIsAnInvalidPose) {
  std::vector<protocol::Quat> long_pose = rotations_;
  long_pose[3] = protocol::Quat(0, 0, 0, 1.5f);
  ASSERT_TRUE(send_pose(*broken_, pose_fields(daemon_->model_id(), 44, long_pose)));
  expect_error_then_service(protocol::ErrorCode::InvalidPose, "joint 3", 44);
}

TEST_F(DaemonErrors, UnknownModelIdIsNamed) {
  ASSERT_TRUE(send_pose(*broken_, pose_fields(99, 45, rotations_)));
  expect_error_then_service(protocol::ErrorCode::UnknownModel, "99", 45);
}

TEST_F(DaemonErrors, FeaturesOnASkinningBaselineAreAnInvalidArgument) {
  protocol::PoseFields fields = pose_fields(daemon_->model_id(), 46, rotations_);
  fields.method = protocol::DeformMethod::Dqs;
  fields.features = protocol::Features::Folding;
  ASSERT_TRUE(send_pose(*broken_, fields));
  expect_error_then_service(protocol::ErrorCode::InvalidArgument, "sweep method only", 46);
}

TEST_F(DaemonErrors, PositionMapsSwitchedOffAreNotAvailable) {
  flatbuffers::FlatBufferBuilder builder;
  const auto pose = protocol::add_pose(builder, pose_fields(daemon_->model_id(), 47, rotations_));
  broken_->send_bytes(protocol::finish_message(
      builder, protocol::CreatePositionMapRequest(builder, pose, 64, 64), 12));
  expect_error_then_service(protocol::ErrorCode::NotAvailable, "switched off", 47);
}

TEST_F(DaemonErrors, BodyTypeFromANewerPeerIsAnUnknownMessage) {
  flatbuffers::FlatBufferBuilder builder;
  const auto body = protocol::CreateListModels(builder);
  const auto message =
      protocol::CreateMessage(builder, 13, static_cast<protocol::Body>(200), body.Union());
  broken_->send_bytes(protocol::finish_frame(builder, message));
  expect_error_then_service(protocol::ErrorCode::UnknownMessage, "200");
}

TEST_F(DaemonErrors, UploadThatIsNotGltfFailsToLoadWithTheReason) {
  flatbuffers::FlatBufferBuilder builder;
  const std::vector<std::uint8_t> junk(300, 0x42);
  broken_->send_bytes(protocol::finish_message(
      builder, protocol::CreateLoadModelDirect(builder, "junk", &junk), 14));
  expect_error_then_service(protocol::ErrorCode::ModelLoadFailed, "junk");
  // A failed load leaves nothing in the store: no .glb of the bytes it could not read.
  for (const fs::directory_entry& entry : fs::directory_iterator(*directory_ / "store"))
    EXPECT_NE(entry.path().extension(), ".glb") << entry.path();
}

TEST_F(DaemonErrors, ClientVanishingMidFrameLeavesOthersServed) {
  {
    FrameClient vanishing(daemon_->port());
    ASSERT_NE(vanishing.hello(""), nullptr);
    flatbuffers::FlatBufferBuilder builder;
    const auto pose = protocol::add_pose(builder, pose_fields(daemon_->model_id(), 1, rotations_));
    const auto frame = protocol::finish_message(builder, pose);
    ASSERT_TRUE(vanishing.send_bytes(frame.first(frame.size() / 2)));  // truncated
  }
  ASSERT_TRUE(send_pose(*healthy_, pose_fields(daemon_->model_id(), 2, rotations_)));
  const protocol::PosedVertices* reply = healthy_->receive_as<protocol::PosedVertices>();
  ASSERT_NE(reply, nullptr);
  EXPECT_EQ(reply->sequence(), 2u);
}

TEST_F(DaemonErrors, SilentConnectionIsClosedAfterTheHelloTimeout) {
  FrameClient silent(daemon_->port());
  const auto connected = std::chrono::steady_clock::now();
  const protocol::Error* error = silent.receive_as<protocol::Error>();
  ASSERT_NE(error, nullptr);
  EXPECT_EQ(error->code(), protocol::ErrorCode::NotAuthenticated);
  EXPECT_TRUE(error->fatal());
  EXPECT_NE(error->message()->str().find("300 ms"), std::string::npos) << error->message()->str();
  // Not before the 300 ms deadline (a little slack for the clocks of two processes).
  EXPECT_GE(std::chrono::steady_clock::now() - connected, std::chrono::milliseconds(250));
  EXPECT_TRUE(silent.closed_by_server());
}

TEST_F(DaemonErrors, ConnectionsBeyondTheLimitAreRefused) {
  FrameClient third(daemon_->port());  // the limit is 3: broken_, healthy_, third
  ASSERT_NE(third.hello(""), nullptr);
  FrameClient fourth(daemon_->port());
  const protocol::Error* error = fourth.receive_as<protocol::Error>();
  ASSERT_NE(error, nullptr);
  EXPECT_EQ(error->code(), protocol::ErrorCode::ConnectionLimit);
  EXPECT_TRUE(error->fatal());
  EXPECT_TRUE(fourth.closed_by_server());
  ASSERT_TRUE(send_pose(third, pose_fields(daemon_->model_id(), 3, rotations_)));
  EXPECT_NE(third.receive_as<protocol::PosedVertices>(), nullptr);
}

}  // namespace
}  // namespace sweepd::test
