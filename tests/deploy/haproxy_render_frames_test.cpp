// A render farm in miniature, with real parts (issue 14 item 5): Debian's haproxy started from
// deploy/haproxy.cfg on loopback in front of two sweepd replicas; two render_frames shards
// (--shard 0/2 and 1/2) render one range through HAProxy at once; one replica is killed with
// SIGKILL in the middle. HAProxy's /readyz check takes it out, the shard that was on it connects
// again (HAProxy sends it to the other replica) and asks again for its frames in flight. Every
// frame is then present, decodes, and equals a render of the same range by one server alone
// within 1e-6 m; no frame was written twice (the shards' rendered counts add up to the range,
// and no rename found its frame already there). Skips, saying so, without haproxy or curl.
#include <ImfInputFile.h>
#include <gtest/gtest.h>

#include <array>
#include <future>
#include <thread>

#include "tests/io/position_map_exr.h"
#include "tests/server/client_run.h"
#include "tests/server/daemon_process.h"
#include "tests/server/haproxy_process.h"
#include "tests/server/http_probe.h"

namespace sweepd::test {
namespace {

using namespace std::chrono_literals;

constexpr int kFirst = 300, kLast = 389;  // 90 frames: long enough to kill a replica mid-run
constexpr int kSide = 96;

io::test_support::DecodedPositionMap read_map(const fs::path& file) {
  Imf::InputFile exr(file.c_str());
  return io::test_support::decode_position_map(exr);
}

TEST(HaproxyRenderFrames, TwoShardsSurviveAKilledReplicaAndMatchOneServer) {
  if (!have_haproxy()) GTEST_SKIP() << "haproxy is not installed (deploy/install-deps.sh)";
  if (!have_program("curl")) GTEST_SKIP() << "curl is not installed (deploy/install-deps.sh)";
  const fs::path clip = fs::path(SWEEPD_SHARED_DATA) / "motion" / "cmu_01_01.bvh";
  const fs::path directory = fresh_directory("haproxy_render_frames");
  std::vector<std::unique_ptr<DaemonProcess>> replicas;
  std::vector<Replica> ports;
  for (int r = 0; r < 2; ++r) {
    const fs::path home = directory / ("replica" + std::to_string(r + 1));
    fs::create_directories(home);
    replicas.push_back(std::make_unique<DaemonProcess>(
        home, std::vector<std::string>{"--token", "t0k", "--http-listen", "127.0.0.1:0",
                                       "--http-port-file", (home / "http_port").string()}));
    ASSERT_TRUE(replicas.back()->running()) << replicas.back()->log();
    ports.push_back({replicas.back()->port(), std::stoi(read_text(home / "http_port"))});
  }
  HaproxyProcess haproxy(fs::path(SWEEPD_SOURCE_DIR) / "deploy" / "haproxy.cfg", directory, ports);
  ASSERT_TRUE(haproxy.running());
  ASSERT_TRUE(haproxy.wait_for("replica1", "UP", 15s)) << haproxy.log();
  ASSERT_TRUE(haproxy.wait_for("replica2", "UP", 15s)) << haproxy.log();

  const fs::path frames = directory / "frames";
  const std::string range = " --frames " + std::to_string(kFirst) + "-" + std::to_string(kLast) +
                            " --width " + std::to_string(kSide) + " --height " +
                            std::to_string(kSide) + " --bvh " + clip.string() + " --token t0k";
  auto shard = [&](int index) {
    return std::async(std::launch::async, [&, index] {
      return run_client(std::string(SWEEPD_RENDER_FRAMES) + " --server 127.0.0.1:" +
                        std::to_string(haproxy.port()) + range + " --timeout 5 --shard " +
                        std::to_string(index) + "/2 -o " + frames.string());
    });
  };
  auto connections_open = [&](std::size_t replica) {
    return metric(curl_get(ports[replica].http_port, "/metrics").body, "sweepd_connections_open");
  };
  auto wait_for_connections = [&](double count) {
    const auto deadline = std::chrono::steady_clock::now() + 15s;
    while (connections_open(0) + connections_open(1) < count &&
           std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(5ms);
    }
  };
  // The second shard starts once the first holds its connection: two connections arriving at
  // once may be placed by HAProxy's two threads on the same replica (leastconn reads the counts
  // before either connection is counted), which is HAProxy's business, not this test's.
  std::future<ClientRun> first = shard(0);
  wait_for_connections(1.0);
  std::future<ClientRun> second = shard(1);
  wait_for_connections(2.0);
  // leastconn put one shard on each replica.
  EXPECT_EQ(connections_open(0), 1.0);
  EXPECT_EQ(connections_open(1), 1.0);
  while (exr_files(frames) < 10 && first.wait_for(5ms) != std::future_status::ready) {
  }
  const int before_kill = exr_files(frames);
  replicas[0]->signal(SIGKILL);
  const ClientRun runs[2] = {first.get(), second.get()};
  ASSERT_LT(before_kill, kLast - kFirst + 1) << "the kill came after the render: nothing tested";
  EXPECT_TRUE(haproxy.wait_for("replica1", "DOWN", 15s)) << haproxy.log();

  int rendered = 0, retried = 0;
  for (const ClientRun& run : runs) {
    ASSERT_EQ(run.exit_code, 0) << run.output << haproxy.log();
    const std::array<int, 5> counts = render_counts(run.output);
    EXPECT_EQ(counts[1], 0) << run.output;
    EXPECT_EQ(counts[0], counts[2]) << "every frame of the shard rendered\n" << run.output;
    EXPECT_EQ(counts[4], 0) << run.output;
    EXPECT_EQ(run.output.find("another process wrote it first"), std::string::npos) << run.output;
    rendered += counts[0];
    retried += counts[3];
  }
  EXPECT_EQ(rendered, kLast - kFirst + 1) << "the shards' slices add up to the range, once";
  EXPECT_GE(retried, 1) << "the killed replica's shard asked again for its frames in flight\n"
                        << runs[0].output << runs[1].output;
  EXPECT_EQ(exr_files(frames), kLast - kFirst + 1) << "one file per frame, no partial left";

  // The same range from the surviving replica alone, directly.
  const fs::path alone = directory / "alone";
  const ClientRun single =
      run_client(std::string(SWEEPD_RENDER_FRAMES) + " --server 127.0.0.1:" +
                 std::to_string(ports[1].protocol_port) + range + " -o " + alone.string());
  ASSERT_EQ(single.exit_code, 0) << single.output;
  float largest = 0.0f;
  for (int frame = kFirst; frame <= kLast; ++frame) {
    char name[32];
    std::snprintf(name, sizeof name, "cmu_01_01.%05d.exr", frame);
    const auto farm = read_map(frames / name), one = read_map(alone / name);
    ASSERT_EQ(farm.positions.size(), one.positions.size()) << name;
    for (std::size_t i = 0; i < farm.positions.size(); ++i)
      largest = std::max(largest, std::abs(farm.positions[i] - one.positions[i]));
    EXPECT_EQ(farm.coverage, one.coverage) << name;
  }
  // Both replicas bound the same default model the same way: the maps should agree to the
  // float; 1e-6 m is the bound.
  EXPECT_LE(largest, 1e-6f);
  std::printf(
      "90 frames through HAProxy, 2 shards, one replica killed after %d: retried %d, "
      "largest difference to one server %.3g m\n",
      before_kill, retried, largest);
  fs::remove_all(directory);
}

}  // namespace
}  // namespace sweepd::test
