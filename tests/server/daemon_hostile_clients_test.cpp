// sweepd against hostile clients (issue 16, item 4): 64 of them — 16 oversized length prefixes
// before Hello, 16 that trickle a large frame, 16 that never read their replies, 16 that send
// garbage after Hello — next to 4 honest clients streaming poses. Every honest pose is answered
// with the library's own vertices, the daemon's peak memory stays within a stated bound, and
// every hostile connection is closed with its reason logged. That runs on TCP and on the Unix
// socket (issue 49 item 5: the other doors; WebSocket's own version, whose oversized messages
// end with a close code, is daemon_websocket_test.cpp's SilentTricklingIdleAndNonReading...).
// Then: an idle connection is closed, and a frame past the shared buffer budget gets
// ResourceExhausted while the session goes on.
#include <gtest/gtest.h>

#include <atomic>
#include <fstream>
#include <sstream>
#include <thread>

#include "io/sweepbind/sweepbind.h"
#include "tests/server/daemon_process.h"
#include "tests/server/hostile_input.h"
#include "tests/server/pose_frames.h"
#include "tests/server/stored_binding.h"

// GCC says TSan by __SANITIZE_THREAD__, Clang (the sanitizer presets' compiler) by __has_feature.
#if defined(__SANITIZE_THREAD__)
#define SWEEPD_THREAD_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define SWEEPD_THREAD_SANITIZER 1
#endif
#endif
#ifdef SWEEPD_THREAD_SANITIZER
constexpr bool kThreadSanitizer = true;
#else
constexpr bool kThreadSanitizer = false;
#endif

namespace sweepd::test::daemon_hostile_clients_test {
namespace {

constexpr std::uint32_t kMannequinJoints = 31;  // mannequin/mannequin.h
constexpr int kHostileEach = 16;
constexpr int kHonestClients = 4;
constexpr int kHonestPoses = 60;
constexpr int kTimeoutMs = 1500;  // frame, send and Hello timeouts of the daemon under test

// A number from /proc/<pid>/status ("VmHWM:", "VmRSS:"), in KiB.
std::size_t status_kib(pid_t pid, const std::string& field) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line))
    if (line.starts_with(field)) return std::stoul(line.substr(field.size()));
  return 0;
}

enum class Transport { kTcp, kUnix };

class HostileClients : public ::testing::TestWithParam<Transport> {
 protected:
  // A client of the transport under test. receive_buffer_bytes > 0: TCP's SO_RCVBUF (a Unix
  // socket has none of its own: what its peer has not read counts against the daemon's send
  // buffer, so a non-reader stalls the daemon's writes all the same).
  std::unique_ptr<FrameClient> connect(const DaemonProcess& daemon, int receive_buffer_bytes = 0) {
    if (GetParam() == Transport::kUnix) return std::make_unique<FrameClient>(socket_);
    return std::make_unique<FrameClient>(daemon.port(), receive_buffer_bytes);
  }

  fs::path socket_;
};

TEST_P(HostileClients, HonestClientsAreServedWhileSixtyFourHostileOnesAreCutOff) {
  const fs::path directory = fresh_directory("hostile");
  socket_ = directory / "sweepd.sock";
  DaemonProcess daemon(
      // The default 20k model: its replies are large enough to fill a non-reader's socket.
      // Strangers' quotas past the 16 oversized peers, which connect faster than their
      // prefixes are read: this test counts each attack's own cut (daemon_strangers_test.cpp
      // sheds strangers).
      directory, {"--mannequin-vertices",
                  "20000",
                  "--position-maps",
                  "0",
                  "--max-connections",
                  "80",
                  "--max-strangers-per-address",
                  "80",
                  "--hello-timeout-ms",
                  std::to_string(kTimeoutMs),
                  "--frame-timeout-ms",
                  std::to_string(kTimeoutMs),
                  "--send-timeout-ms",
                  std::to_string(kTimeoutMs),
                  "--idle-timeout-ms",
                  "0",
                  "--max-buffered-bytes",
                  std::to_string(64 << 20),
                  "--unix-socket",
                  socket_.string()});
  ASSERT_TRUE(daemon.running()) << daemon.log();
  const deform::BoundModel mannequin =
      io::load_sweepbind(stored_binding(directory / "store", "mannequin"));
  const std::vector<glm::quat> rotations = bent_rotations(kMannequinJoints);
  const std::vector<protocol::Quat> wire = to_wire(rotations);
  const Deformed expected = library_deformation(mannequin, rotations, deform::DeformMethod::kSweep);
  {
    const std::unique_ptr<FrameClient> warm = connect(daemon);
    ASSERT_NE(warm->hello(""), nullptr);
    ASSERT_TRUE(send_pose(*warm, pose_fields(daemon.model_id(), 1, wire)));
    ASSERT_NE(warm->receive_as<protocol::PosedVertices>(), nullptr);
  }
  const std::size_t rss_before_kib = status_kib(daemon.pid(), "VmRSS:");

  // Hostile 1: a 1 MiB length prefix before Hello (the limit there is 64 KiB).
  std::vector<std::unique_ptr<FrameClient>> oversized, tricklers, non_readers, garbage;
  for (int i = 0; i < kHostileEach; ++i) {
    oversized.push_back(connect(daemon));
    ASSERT_TRUE(oversized.back()->send_bytes(length_prefix(1u << 20)));
  }
  // Hostile 2: Hello, then a 16 MiB frame trickled a byte at a time (the old reader reserved
  // the whole declared frame at its prefix: 16 × 16 MiB).
  for (int i = 0; i < kHostileEach; ++i) {
    tricklers.push_back(connect(daemon));
    ASSERT_NE(tricklers.back()->hello(""), nullptr);
    ASSERT_TRUE(tricklers.back()->send_bytes(length_prefix(16u << 20)));
  }
  std::atomic<bool> trickling = true;
  std::thread trickle([&] {
    const std::uint8_t byte = 0x42;
    while (trickling) {
      for (auto& client : tricklers) client->send_bytes({&byte, 1});
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  });
  // Hostile 3: Hello, 40 poses (about 10 MB of replies), and never a byte read (a 4 KiB receive
  // buffer): the server's writes stall.
  for (int i = 0; i < kHostileEach; ++i) {
    non_readers.push_back(connect(daemon, 4096));
    ASSERT_NE(non_readers.back()->hello(""), nullptr);
    for (int p = 0; p < 40; ++p)
      ASSERT_TRUE(send_pose(*non_readers.back(), pose_fields(daemon.model_id(), p, wire)));
  }
  // Hostile 4: Hello, then 20 frames of garbage (16 bad frames close a connection).
  const std::vector<std::uint8_t> junk = garbage_frame();
  for (int i = 0; i < kHostileEach; ++i) {
    garbage.push_back(connect(daemon));
    ASSERT_NE(garbage.back()->hello(""), nullptr);
    for (int f = 0; f < 20; ++f) garbage.back()->send_bytes(junk);
  }

  // The honest clients, meanwhile: every pose answered with the library's vertices.
  std::atomic<int> answered = 0, wrong = 0;
  std::vector<std::thread> honest;
  for (int c = 0; c < kHonestClients; ++c) {
    honest.emplace_back([&, c] {
      const std::unique_ptr<FrameClient> connection = connect(daemon);
      FrameClient& client = *connection;
      if (client.hello("") == nullptr) return;
      for (int p = 0; p < kHonestPoses; ++p) {
        if (!send_pose(client, pose_fields(daemon.model_id(), 100 * c + p, wire))) return;
        const protocol::PosedVertices* reply = client.receive_as<protocol::PosedVertices>();
        if (reply == nullptr) return;
        std::vector<glm::vec3> positions(expected.positions.size());
        const bool copied = protocol::copy_positions(
            *reply, {reinterpret_cast<float*>(positions.data()), 3 * positions.size()});
        if (!copied || reply->sequence() != static_cast<std::uint64_t>(100 * c + p) ||
            positions != expected.positions)
          ++wrong;
        ++answered;
      }
    });
  }
  for (std::thread& thread : honest) thread.join();
  EXPECT_EQ(answered, kHonestClients * kHonestPoses);
  EXPECT_EQ(wrong, 0);

  // Every hostile connection is closed, the ones that read with the fatal Error they earned.
  for (auto& client : oversized)
    EXPECT_EQ(last_error_before_close(*client), protocol::ErrorCode::FrameTooLarge);
  for (auto& client : garbage)
    EXPECT_EQ(last_error_before_close(*client), protocol::ErrorCode::BadFrame);
  for (auto& client : tricklers)
    EXPECT_EQ(last_error_before_close(*client), protocol::ErrorCode::BadFrame);
  trickling = false;
  trickle.join();
  // The non-readers get no Error (they would not read it): the send deadline closes them.
  std::this_thread::sleep_for(std::chrono::milliseconds(2 * kTimeoutMs));
  const std::string log = daemon.log();
  const auto each = static_cast<std::size_t>(kHostileEach);
  EXPECT_EQ(log_lines(log, "connection_cut", ""), 4 * each) << log.substr(0, 4000);
  EXPECT_EQ(log_lines(log, "connection_cut", "before Hello a frame may have at most 65536 bytes"),
            each);
  EXPECT_EQ(log_lines(log, "connection_cut", "was not whole within 1500 ms"), each);
  EXPECT_EQ(log_lines(log, "connection_cut", "took no reply bytes for 1500 ms"), each);
  EXPECT_EQ(log_lines(log, "connection_cut", "16 bad frames"), each);

  // Peak memory: what was resident before, plus the non-readers' stalled replies (16 × 8
  // poses in flight × 0.24 MB = 31 MB) and each connection's read buffer and kept frame
  // storage (80 × 128 KiB = 10 MiB): 96 MiB leaves room for allocator slack. The old reader
  // alone would have held 16 × 16 MiB for the tricklers. Under ThreadSanitizer each byte the
  // daemon touches also costs shadow memory and each thread its clocks (its manual: 5-10x
  // memory): it measured 170 MiB, so the bound is 4x there. That no longer separates the old
  // reader's 256 MiB as the 1x bound does; the Release and ASan runs of this test keep that.
  constexpr std::size_t kSanitizerFactor = kThreadSanitizer ? 4 : 1;
  const std::size_t peak_kib = status_kib(daemon.pid(), "VmHWM:");
  EXPECT_LT(peak_kib, rss_before_kib + kSanitizerFactor * 96 * 1024)
      << "before " << rss_before_kib << " KiB, peak " << peak_kib << " KiB";
  std::printf("daemon RSS before the hostile clients %zu KiB, peak %zu KiB\n", rss_before_kib,
              peak_kib);
  fs::remove_all(directory);
}

INSTANTIATE_TEST_SUITE_P(Transports, HostileClients,
                         ::testing::Values(Transport::kTcp, Transport::kUnix),
                         [](const ::testing::TestParamInfo<Transport>& info) {
                           return info.param == Transport::kTcp ? "Tcp" : "Unix";
                         });

TEST(DaemonHostileClients, AnIdleConnectionIsClosedAndABusyOneIsNot) {
  const fs::path directory = fresh_directory("idle");
  DaemonProcess daemon(directory, {"--position-maps", "0", "--idle-timeout-ms", "400"});
  ASSERT_TRUE(daemon.running()) << daemon.log();
  const std::vector<protocol::Quat> wire = to_wire(bent_rotations(kMannequinJoints));
  FrameClient idle(daemon.port()), busy(daemon.port());
  ASSERT_NE(idle.hello(""), nullptr);
  ASSERT_NE(busy.hello(""), nullptr);
  // The busy client sends a pose every 100 ms for 1.2 s: three idle timeouts, never idle.
  for (int p = 0; p < 12; ++p) {
    ASSERT_TRUE(send_pose(busy, pose_fields(daemon.model_id(), p, wire)));
    ASSERT_NE(busy.receive_as<protocol::PosedVertices>(), nullptr) << "pose " << p;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  const protocol::Error* error = idle.receive_as<protocol::Error>();
  ASSERT_NE(error, nullptr);
  EXPECT_TRUE(error->fatal());
  EXPECT_NE(error->message()->str().find("no request for 400 ms"), std::string::npos)
      << error->message()->str();
  EXPECT_TRUE(idle.closed_by_server());
  fs::remove_all(directory);
}

TEST(DaemonHostileClients, AFramePastTheSharedBudgetIsRefusedAndTheSessionGoesOn) {
  const fs::path directory = fresh_directory("budget");
  DaemonProcess daemon(directory,
                       {"--position-maps", "0", "--max-buffered-bytes", std::to_string(1 << 20)});
  ASSERT_TRUE(daemon.running()) << daemon.log();
  FrameClient client(daemon.port());
  ASSERT_NE(client.hello(""), nullptr);
  expect_frame_past_budget_refused(client, daemon.model_id());
  fs::remove_all(directory);
}

}  // namespace
}  // namespace sweepd::test::daemon_hostile_clients_test
