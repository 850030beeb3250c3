// A render farm in miniature, with real parts (issue 14 items 2 and 5): Debian's haproxy started
// from deploy/haproxy.cfg on loopback in front of two sweepd replicas.
//
// 1. The replicas share one store directory (a ReadWriteMany volume). A model is uploaded once
//    through HAProxy; two render_frames shards (--shard 0/2 and 1/2) name it and render one range
//    through HAProxy at once; one replica is killed with SIGKILL in the middle. The replica that
//    did not bind the model adopted it from the store; HAProxy's /readyz check takes the killed
//    one out, the shard that was on it connects again (to the other replica) and asks again for
//    its frames in flight. Every frame is then present, decodes, and equals a render of the same
//    range by one server alone within 1e-6 m; no frame was written twice (the shards' rendered
//    counts add up to the range, and no rename found its frame already there).
// 2. The replicas have stores of their own. One shard uploads the model (--model-file) through
//    HAProxy; the replica holding it is killed; the reconnect reaches the other replica, which
//    answers the model's content id with UnknownModel; render_frames uploads again and
//    finishes the range.
// Skips, saying so, without haproxy or curl.
#include <ImfInputFile.h>
#include <gtest/gtest.h>

#include <array>
#include <future>
#include <thread>

#include "io/gltf/gltf_save.h"
#include "mannequin/mannequin.h"
#include "tests/io/position_map_exr.h"
#include "tests/server/client_run.h"
#include "tests/server/daemon_process.h"
#include "tests/server/haproxy_process.h"
#include "tests/server/http_probe.h"

namespace sweepd::test {
namespace {

using namespace std::chrono_literals;

constexpr int kFirst = 300, kLast = 389;  // 90 frames: long enough to kill a replica mid-run
constexpr int kFrames = kLast - kFirst + 1;
constexpr int kSide = 96;

io::test_support::DecodedPositionMap read_map(const fs::path& file) {
  Imf::InputFile exr(file.c_str());
  return io::test_support::decode_position_map(exr);
}

class HaproxyRenderFrames : public ::testing::Test {
 protected:
  // Two replicas (sharing `directory_/store` when `shared_store`) behind HAProxy, both UP.
  void start(const std::string& name, bool shared_store) {
    directory_ = fresh_directory(name);
    for (int r = 0; r < 2; ++r) {
      const fs::path home = directory_ / ("replica" + std::to_string(r + 1));
      fs::create_directories(home);
      std::vector<std::string> args = {"--token",          "t0k",
                                       "--http-listen",    "127.0.0.1:0",
                                       "--http-port-file", (home / "http_port").string()};
      if (shared_store) args.insert(args.end(), {"--store-dir", (directory_ / "store").string()});
      replicas_.push_back(std::make_unique<DaemonProcess>(home, args));
      ASSERT_TRUE(replicas_.back()->running()) << replicas_.back()->log();
      ports_.push_back({replicas_.back()->port(), std::stoi(read_text(home / "http_port"))});
    }
    haproxy_ = std::make_unique<HaproxyProcess>(
        fs::path(SWEEPD_SOURCE_DIR) / "deploy" / "haproxy.cfg", directory_, ports_);
    ASSERT_TRUE(haproxy_->running()) << "haproxy did not start; log:\n" << haproxy_->log();
    ASSERT_TRUE(haproxy_->wait_for("replica1", "UP", 15s)) << haproxy_->log();
    ASSERT_TRUE(haproxy_->wait_for("replica2", "UP", 15s)) << haproxy_->log();
    model_file_ = directory_ / "farm.glb";
    io::save_gltf(mannequin::make_mannequin({.target_vertices = 3000}), model_file_);
  }
  void TearDown() override {
    if (!HasFailure() && !directory_.empty()) fs::remove_all(directory_);
  }

  double connections_open(std::size_t replica) const {
    return metric(curl_get(ports_[replica].http_port, "/metrics").body, "sweepd_connections_open");
  }
  // Waits until the replicas hold `count` protocol connections together (15 s at most).
  void wait_for_connections(double count) const {
    const auto deadline = std::chrono::steady_clock::now() + 15s;
    while (connections_open(0) + connections_open(1) < count &&
           std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(5ms);
    }
  }

  // render_frames against `server` on the range, with `extra` flags, into `frames`.
  std::string render_command(const std::string& server, const std::string& extra,
                             const fs::path& frames) const {
    return std::string(SWEEPD_RENDER_FRAMES) + " --server " + server + " --frames " +
           std::to_string(kFirst) + "-" + std::to_string(kLast) + " --width " +
           std::to_string(kSide) + " --height " + std::to_string(kSide) + " --bvh " +
           clip_.string() + " --token t0k " + extra + " -o " + frames.string();
  }

  // render_frames through HAProxy, with a 5 s timeout, started now.
  std::future<ClientRun> render(const std::string& extra, const fs::path& frames) const {
    const std::string command = render_command("127.0.0.1:" + std::to_string(haproxy_->port()),
                                               "--timeout 5 " + extra, frames);
    return std::async(std::launch::async, [command] { return run_client(command); });
  }

  // Kills with SIGKILL the replica that holds a connection once `frames` holds 10 files, and
  // returns how many it held then.
  int kill_a_busy_replica_midway(const fs::path& frames, std::future<ClientRun>& run) {
    while (exr_files(frames) < 10 && run.wait_for(5ms) != std::future_status::ready) {
    }
    const int before_kill = exr_files(frames);
    killed_ = connections_open(0) >= 1.0 ? 0 : 1;
    replicas_[killed_]->signal(SIGKILL);
    return before_kill;
  }

  // Every frame of the range in `frames` equals the one in `reference` within 1e-6 m: both
  // replicas bound the same model the same way, so the maps should agree to the float.
  void expect_frames_equal(const fs::path& frames, const fs::path& reference) const {
    float largest = 0.0f;
    for (int frame = kFirst; frame <= kLast; ++frame) {
      char name[32];
      std::snprintf(name, sizeof name, "cmu_01_01.%05d.exr", frame);
      const auto farm = read_map(frames / name), one = read_map(reference / name);
      ASSERT_EQ(farm.positions.size(), one.positions.size()) << name;
      for (std::size_t i = 0; i < farm.positions.size(); ++i)
        largest = std::max(largest, std::abs(farm.positions[i] - one.positions[i]));
      EXPECT_EQ(farm.coverage, one.coverage) << name;
    }
    EXPECT_LE(largest, 1e-6f);
    std::printf("largest difference to one server %.3g m\n", largest);
  }

  // The same range from the surviving replica alone, directly, with `extra` flags.
  fs::path render_alone(const std::string& extra) const {
    const fs::path alone = directory_ / "alone";
    const ClientRun single = run_client(render_command(
        "127.0.0.1:" + std::to_string(ports_[1 - killed_].protocol_port), extra, alone));
    EXPECT_EQ(single.exit_code, 0) << single.output;
    return alone;
  }

  const fs::path clip_ = fs::path(SWEEPD_SHARED_DATA) / "motion" / "cmu_01_01.bvh";
  fs::path directory_, model_file_;
  std::vector<std::unique_ptr<DaemonProcess>> replicas_;
  std::vector<Replica> ports_;
  std::unique_ptr<HaproxyProcess> haproxy_;
  std::size_t killed_ = 0;
};

#define SKIP_WITHOUT_HAPROXY_OR_CURL()                                                           \
  do {                                                                                           \
    if (!have_haproxy()) GTEST_SKIP() << "haproxy is not installed (deploy/install-deps.sh)";    \
    if (!have_program("curl")) GTEST_SKIP() << "curl is not installed (deploy/install-deps.sh)"; \
  } while (false)

TEST_F(HaproxyRenderFrames, TwoShardsOnASharedStoreSurviveAKilledReplicaAndMatchOneServer) {
  SKIP_WITHOUT_HAPROXY_OR_CURL();
  start("haproxy_render_shared", /*shared_store=*/true);
  if (HasFatalFailure()) return;
  // Uploaded once, through HAProxy, to whichever replica it picks.
  {
    FrameClient uploader(haproxy_->port());
    ASSERT_NE(uploader.hello("t0k"), nullptr);
    flatbuffers::FlatBufferBuilder builder;
    const std::vector<std::uint8_t> glb = read_bytes(model_file_);
    uploader.send_bytes(protocol::finish_message(
        builder, protocol::CreateLoadModelDirect(builder, "farm", &glb), 1));
    ASSERT_NE(uploader.receive_as<protocol::ModelInfo>(), nullptr);
  }
  const fs::path frames = directory_ / "frames";
  // The second shard starts once the first holds its connection: two connections arriving at
  // once may be placed by HAProxy's two threads on the same replica (leastconn reads the counts
  // before either connection is counted: 23 times in 200 here), which is HAProxy's business.
  std::future<ClientRun> first = render("--model farm --shard 0/2", frames);
  wait_for_connections(1.0);
  std::future<ClientRun> second = render("--model farm --shard 1/2", frames);
  wait_for_connections(2.0);
  // leastconn put one shard on each replica.
  EXPECT_EQ(connections_open(0), 1.0);
  EXPECT_EQ(connections_open(1), 1.0);
  const int before_kill = kill_a_busy_replica_midway(frames, first);
  const ClientRun runs[2] = {first.get(), second.get()};
  ASSERT_LT(before_kill, kFrames) << "the kill came after the render: nothing tested";
  EXPECT_TRUE(haproxy_->wait_for("replica" + std::to_string(killed_ + 1), "DOWN", 15s))
      << haproxy_->log();

  int rendered = 0, retried = 0;
  for (const ClientRun& run : runs) {
    ASSERT_EQ(run.exit_code, 0) << run.output << haproxy_->log();
    const std::array<int, 5> counts = render_counts(run.output);
    EXPECT_EQ(counts[1], 0) << run.output;
    EXPECT_EQ(counts[0], counts[2]) << "every frame of the shard rendered\n" << run.output;
    EXPECT_EQ(counts[4], 0) << run.output;
    EXPECT_EQ(run.output.find("another process wrote it first"), std::string::npos) << run.output;
    rendered += counts[0];
    retried += counts[3];
  }
  EXPECT_EQ(rendered, kFrames) << "the shards' slices add up to the range, once";
  // Both replicas serve "farm": one bound it, the other found it in the shared store.
  const std::string adopted = "\"event\":\"model_adopted\"";
  EXPECT_NE((replicas_[0]->log() + replicas_[1]->log()).find(adopted), std::string::npos)
      << replicas_[0]->log() << replicas_[1]->log();
  EXPECT_GE(retried, 1) << "the killed replica's shard asked again for its frames in flight\n"
                        << runs[0].output << runs[1].output;
  EXPECT_EQ(exr_files(frames), kFrames) << "one file per frame, no partial left";
  // One binding per model in the shared store: the default mannequin and "farm".
  int bindings = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(directory_ / "store"))
    bindings += entry.path().extension() == ".sweepbind";
  EXPECT_EQ(bindings, 2);

  expect_frames_equal(frames, render_alone("--model farm"));
  std::printf("%d frames through HAProxy, 2 shards, one replica killed after %d: retried %d\n",
              kFrames, before_kill, retried);
}

TEST_F(HaproxyRenderFrames, AReplicaWithoutTheModelGetsItUploadedAgain) {
  SKIP_WITHOUT_HAPROXY_OR_CURL();
  start("haproxy_render_own_stores", /*shared_store=*/false);
  if (HasFatalFailure()) return;
  const fs::path frames = directory_ / "frames";
  std::future<ClientRun> run = render("--model-file " + model_file_.string(), frames);
  wait_for_connections(1.0);
  const int before_kill = kill_a_busy_replica_midway(frames, run);
  const ClientRun result = run.get();
  ASSERT_LT(before_kill, kFrames) << "the kill came after the render: nothing tested";
  ASSERT_EQ(result.exit_code, 0) << result.output << haproxy_->log();
  const std::array<int, 5> counts = render_counts(result.output);
  EXPECT_EQ(counts[0], kFrames) << result.output;
  EXPECT_EQ(counts[4], 0) << result.output;
  // The survivor answered the model's content id with UnknownModel, then bound the upload.
  EXPECT_NE(result.output.find("uploaded " + model_file_.string() + " 2 times"), std::string::npos)
      << result.output;
  EXPECT_NE(replicas_[1 - killed_]->log().find("no model with content id"), std::string::npos)
      << replicas_[1 - killed_]->log();
  EXPECT_EQ(exr_files(frames), kFrames);
  expect_frames_equal(frames, render_alone("--model-file " + model_file_.string()));
}

}  // namespace
}  // namespace sweepd::test
