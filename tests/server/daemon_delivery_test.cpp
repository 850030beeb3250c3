// sweepd's pose scheduling: InOrder answers every pose in order and stops reading a client
// that does not read its replies (backpressure); LatestWins drops stale poses and counts them.
#include <gtest/gtest.h>

#include "tests/server/daemon_process.h"
#include "tests/server/pose_frames.h"

namespace sweepd::test {
namespace {

constexpr std::uint32_t kMannequinJoints = 31;  // mannequin/mannequin.h: 31 joints
constexpr std::uint32_t kMaxInFlight = 4;

class DaemonDelivery : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    directory_ = new fs::path(fresh_directory("delivery"));
    daemon_ =
        // The default 20k model: replies large enough to fill a client's unread socket.
        new DaemonProcess(*directory_, {"--mannequin-vertices", "20000", "--max-poses-in-flight",
                                        std::to_string(kMaxInFlight)});
  }
  static void TearDownTestSuite() {
    delete daemon_;
    fs::remove_all(*directory_);
    delete directory_;
  }
  void SetUp() override { ASSERT_TRUE(daemon_->running()); }

  // `count` poses in one send, as a client that streams faster than the server deforms.
  static std::vector<std::uint8_t> pipelined_poses(std::uint64_t count) {
    std::vector<std::uint8_t> bytes;
    const std::vector<protocol::Quat> rotations = to_wire(bent_rotations(kMannequinJoints));
    for (std::uint64_t s = 1; s <= count; ++s) {
      flatbuffers::FlatBufferBuilder builder;
      const auto frame = protocol::finish_message(
          builder, protocol::add_pose(builder, pose_fields(daemon_->model_id(), s, rotations)));
      bytes.insert(bytes.end(), frame.begin(), frame.end());
    }
    return bytes;
  }

  static fs::path* directory_;
  static DaemonProcess* daemon_;
};
fs::path* DaemonDelivery::directory_ = nullptr;
DaemonProcess* DaemonDelivery::daemon_ = nullptr;

TEST_F(DaemonDelivery, InOrderAnswersEveryPoseInOrder) {
  FrameClient client(daemon_->port());
  ASSERT_NE(client.hello(""), nullptr);
  constexpr std::uint64_t kPoses = 40;
  ASSERT_TRUE(client.send_bytes(pipelined_poses(kPoses)));
  for (std::uint64_t s = 1; s <= kPoses; ++s) {
    const protocol::PosedVertices* reply = client.receive_as<protocol::PosedVertices>();
    ASSERT_NE(reply, nullptr);
    EXPECT_EQ(reply->sequence(), s);
    EXPECT_EQ(reply->dropped_before(), 0u);
  }
}

TEST_F(DaemonDelivery, ByeAfterPipelinedPosesAnswersThemAllBeforeClosing) {
  FrameClient client(daemon_->port());
  ASSERT_NE(client.hello(""), nullptr);
  constexpr std::uint64_t kPoses = 6;
  std::vector<std::uint8_t> bytes = pipelined_poses(kPoses);
  flatbuffers::FlatBufferBuilder builder;
  const auto bye = protocol::finish_message(builder, protocol::CreateByeDirect(builder, "done"));
  bytes.insert(bytes.end(), bye.begin(), bye.end());
  ASSERT_TRUE(client.send_bytes(bytes));
  for (std::uint64_t s = 1; s <= kPoses; ++s) {
    const protocol::PosedVertices* reply = client.receive_as<protocol::PosedVertices>();
    ASSERT_NE(reply, nullptr) << "pose " << s << " was not answered before closing";
    EXPECT_EQ(reply->sequence(), s);
  }
  EXPECT_TRUE(client.closed_by_server());
}

TEST_F(DaemonDelivery, LatestWinsDropsStalePosesAndCountsThem) {
  FrameClient client(daemon_->port());
  ASSERT_NE(client.hello("", protocol::PoseDelivery::LatestWins), nullptr);
  constexpr std::uint64_t kPoses = 40;
  ASSERT_TRUE(client.send_bytes(pipelined_poses(kPoses)));
  std::uint64_t replies = 0, dropped = 0, last = 0;
  while (last < kPoses) {
    const protocol::PosedVertices* reply = client.receive_as<protocol::PosedVertices>();
    ASSERT_NE(reply, nullptr);
    EXPECT_GT(reply->sequence(), last) << "replies keep pose order";
    last = reply->sequence();
    ++replies;
    dropped += reply->dropped_before();
  }
  // Every pose is either answered or counted as dropped, and the newest is always answered.
  EXPECT_EQ(replies + dropped, kPoses);
  // 40 poses arrive in one ~20 kB segment, parsed in microseconds, while one 20k-vertex
  // deformation takes about a millisecond: most must be dropped.
  EXPECT_GT(dropped, kPoses / 2);
}

TEST_F(DaemonDelivery, InOrderStopsReadingAClientThatDoesNotReadItsReplies) {
  FrameClient lazy(daemon_->port());
  const protocol::Welcome* welcome = lazy.hello("");
  ASSERT_NE(welcome, nullptr);
  EXPECT_EQ(welcome->max_poses_in_flight(), kMaxInFlight);
  const std::uint64_t lazy_id = welcome->connection_id();
  // 400 poses (~200 kB in) would produce ~93 MB of replies: far more than the socket
  // buffers hold, so the server must stop reading long before the last pose.
  constexpr std::uint64_t kPoses = 400;
  ASSERT_TRUE(lazy.send_bytes(pipelined_poses(kPoses)));
  std::this_thread::sleep_for(std::chrono::milliseconds(500));

  FrameClient observer(daemon_->port());
  ASSERT_NE(observer.hello(""), nullptr);
  flatbuffers::FlatBufferBuilder builder;
  observer.send_bytes(protocol::finish_message(builder, protocol::CreateStatsRequest(builder)));
  const protocol::Stats* stats = observer.receive_as<protocol::Stats>();
  ASSERT_NE(stats, nullptr);
  std::uint64_t received = 0;
  for (const protocol::ConnectionStats* c : *stats->connections()) {
    if (c->connection_id() == lazy_id) received = c->poses_received();
  }
  RecordProperty("poses_read_before_backpressure", static_cast<int>(received));
  EXPECT_GT(received, 0u);
  EXPECT_LT(received, kPoses / 2) << "the server kept reading a client that never read";

  for (std::uint64_t s = 1; s <= kPoses; ++s) {  // once read, every pose is answered, in order
    const protocol::PosedVertices* reply = lazy.receive_as<protocol::PosedVertices>();
    ASSERT_NE(reply, nullptr);
    ASSERT_EQ(reply->sequence(), s);
  }
}

}  // namespace
}  // namespace sweepd::test
