// A model per sender (issue 51: "which model a stream drives ... per sender"): two VMC receivers,
// `--vmc-listen 127.0.0.1:0=FEMALE --vmc-listen 127.0.0.1:0=RiggedFigure`, each its own port and
// its own stream, named by its model, as a VMC receiving app listens on a port per avatar. Two
// liblo senders on two threads replay at the same time CMU 01_01 retargeted onto the Mixamo
// heavy female (corpus) and CMU 01_03 retargeted onto the RiggedFigure, each to its own
// receiver; two subscribers, one per stream (SubscribeStream by the model's name; one over TCP,
// one over the Unix socket), get the meshes. Each mesh equals PoseFromClip's of its own model and
// clip frame within 1e-5 m: neither sender's frames pose the other's model, nor do its bones mix
// into the other's stream. /metrics counts each stream apart. (Not the shared male: its CMU rig
// has joints no HumanBodyBones bone reaches, Neck1 and the hip links, which PoseFromClip turns
// and a VMC stream cannot: docs/vmc.md.)
#include <gtest/gtest.h>
#include <lo/lo.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <thread>

#include "client/clip_upload.h"
#include "client/connection.h"
#include "deform/rig/human_body_bones.h"
#include "io/bvh/bvh_load.h"
#include "io/files/file_bytes.h"
#include "io/sweepbind/sweepbind.h"
#include "metrics/quality_metrics.h"
#include "motion/retarget.h"
#include "tests/server/daemon_process.h"
#include "tests/server/http_probe.h"
#include "tests/server/stored_binding.h"
#include "tests/server/sweepctl_remote.h"
#include "tests/server/vmc_replay.h"

namespace sweepd::test {
namespace {

namespace pb = sweepd::protocol;

const fs::path kSharedModels = fs::path(SWEEPD_SHARED_DATA) / "models";
const fs::path kSharedMotion = fs::path(SWEEPD_SHARED_DATA) / "motion";
constexpr int kFramesEach = 12;

// One performer: a model, the clip its sender replays, the frames sent, and its subscriber.
struct VmcPerformer {
  std::string model_name;
  fs::path model_file;
  std::string clip_file;
  int vmc_port = 0;
  std::uint32_t model_id = 0;
  std::string clip_id;
  std::vector<int> clip_frames;                  // the stream's frame k is clip_frames[k - 1]
  std::vector<std::vector<VmcBone>> sent_bones;  // the same frames' bones, as sent
  std::unique_ptr<client::Connection> subscriber;
  std::vector<std::pair<std::uint64_t, std::vector<glm::vec3>>> received;  // (frame, mesh)
};

// `address`: "HOST:PORT" or "unix:PATH".
std::unique_ptr<client::Connection> open_connection(const std::string& address,
                                                    pb::PoseDelivery delivery) {
  auto connection = std::make_unique<client::Connection>(address);
  connection->set_receive_timeout(std::chrono::seconds(60));
  connection->hello("", "daemon_vmc_streams_test", delivery);
  return connection;
}

TEST(DaemonVmcStreams, TwoSendersPoseTwoModelsAtOnceEachAsPoseFromClipDoes) {
  std::vector<VmcPerformer> performers(2);
  performers[0].model_name = "makehuman_female_old_heavy_mixamo";
  performers[0].model_file = kSharedModels / "corpus" / "makehuman_female_old_heavy_mixamo.glb";
  performers[0].clip_file = "cmu_01_01.bvh";
  // Loaded by name from --model-dir (a .gltf beside its .bin).
  performers[1].model_name = "RiggedFigure";
  performers[1].model_file = kSharedModels / "RiggedFigure" / "RiggedFigure.gltf";
  performers[1].clip_file = "cmu_01_03.bvh";
  for (const VmcPerformer& performer : performers) {
    if (!fs::exists(performer.model_file)) GTEST_SKIP() << "no shared data";
  }
  ScratchDirectory directory("vmc_streams");
  const std::string unix_socket = (directory / "sweepd.sock").string();
  DaemonProcess daemon(directory.path(),
                       {"--vmc-listen", "127.0.0.1:0=" + performers[0].model_name, "--vmc-listen",
                        "127.0.0.1:0=" + performers[1].model_name, "--unix-socket", unix_socket,
                        "--model-dir", (kSharedModels / "RiggedFigure").string(), "--vmc-port-file",
                        (directory / "vmc_ports").string(), "--http-listen", "127.0.0.1:0",
                        "--http-port-file", (directory / "http_port").string()});
  ASSERT_TRUE(daemon.running()) << daemon.log();
  {
    std::istringstream ports(read_text(directory / "vmc_ports"));
    for (VmcPerformer& performer : performers) ports >> performer.vmc_port;
  }
  ASSERT_NE(performers[0].vmc_port, 0) << "a port a line, in --vmc-listen's order";
  ASSERT_NE(performers[1].vmc_port, 0);
  ASSERT_NE(performers[0].vmc_port, performers[1].vmc_port);
  const int http_port = std::stoi(read_text(directory / "http_port"));

  const std::string tcp = "127.0.0.1:" + std::to_string(daemon.port());
  std::unique_ptr<client::Connection> main = open_connection(tcp, pb::PoseDelivery::InOrder);
  for (VmcPerformer& performer : performers) {
    performer.model_id =
        (performer.model_file.extension() == ".glb"
             ? main->load_model(performer.model_name, read_bytes(performer.model_file))
             : main->load_model(performer.model_name))
            .model_id();
    const deform::BoundModel bound =
        io::load_sweepbind(stored_binding(directory / "store", performer.model_id));
    ASSERT_EQ(deform::map_human_body_bones(bound.model.skeleton, bound.rig)[0], 0)
        << performer.model_name << ": the hips are joint 0, their Bone/Pos the root translation";
    const std::vector<char> text = file_bytes(kSharedMotion / performer.clip_file);
    performer.clip_id = client::upload_clip(*main, performer.clip_file, {text.data(), text.size()})
                            .clip_id()
                            ->str();
    const motion::Retargeter played(io::load_bvh(kSharedMotion / performer.clip_file), bound.model);
    for (int step = 0; step < kFramesEach; ++step) {
      const int frame = step * (played.frame_count() - 1) / (kFramesEach - 1);
      performer.clip_frames.push_back(frame);
      performer.sent_bones.push_back(vmc_pose_bones(bound, played.pose_at_frame(frame)));
    }
    // One subscribes over TCP, the other over the Unix socket.
    performer.subscriber = open_connection(
        &performer == &performers[0] ? tcp : "unix:" + unix_socket, pb::PoseDelivery::LatestWins);
    EXPECT_EQ(subscribe_to_stream(*performer.subscriber, performer.model_name), performer.model_id);
  }

  // Both senders at once, a frame each every 10 ms, from their own sockets.
  std::vector<std::thread> senders;
  for (const VmcPerformer& performer : performers) {
    senders.emplace_back([&performer] {
      lo_address to = lo_address_new("127.0.0.1", std::to_string(performer.vmc_port).c_str());
      for (int step = 0; step < kFramesEach; ++step) {
        lo_bundle bundle = vmc_frame_bundle(performer.sent_bones[step], 0.01f * step);
        EXPECT_EQ(lo_send_bundle(to, bundle), static_cast<int>(lo_bundle_length(bundle)));
        lo_bundle_free_recursive(bundle);
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
      }
      lo_address_free(to);
    });
  }
  for (std::thread& sender : senders) sender.join();
  // Latest wins: a subscriber may miss frames that came faster than they were deformed, never
  // the last one.
  for (VmcPerformer& performer : performers) {
    std::uint64_t frame = 0;
    while (frame < kFramesEach) {
      const pb::PosedVertices& streamed = performer.subscriber->expect<pb::PosedVertices>();
      EXPECT_EQ(streamed.model_id(), performer.model_id);
      EXPECT_GT(streamed.sequence(), frame) << "frames come in order";
      frame = streamed.sequence();
      performer.received.emplace_back(frame, positions_of(streamed));
    }
  }
  // The metrics now, while both senders count as senders (an address within the last 10 s):
  // the comparisons below pose 24 frames again, which under a sanitizer took longer than that.
  const std::string page = curl_get(http_port, "/metrics").body;
  for (const VmcPerformer& performer : performers) {
    double largest_apart = 0.0;
    for (const auto& [frame, mesh] : performer.received) {
      const int clip_frame_number = performer.clip_frames.at(frame - 1);
      const std::vector<glm::vec3> expected =
          pose_from_clip_mesh(*main, performer.model_id, performer.clip_id,
                              static_cast<std::uint32_t>(clip_frame_number));
      const double apart = metrics::largest_distance(mesh, expected);
      EXPECT_LE(apart, kVmcSameMesh) << performer.model_name << " stream frame " << frame
                                     << " (clip frame " << clip_frame_number << ")";
      largest_apart = std::max(largest_apart, apart);
    }
    std::printf("stream %s (%s): %zu of %d frames delivered, at most %g m from PoseFromClip\n",
                performer.model_name.c_str(), performer.clip_file.c_str(),
                performer.received.size(), kFramesEach, largest_apart);
  }

  for (const VmcPerformer& performer : performers) {
    const std::string& stream = performer.model_name;
    EXPECT_EQ(metric(page, vmc_series("sweepd_vmc_packets_total", stream)), kFramesEach) << stream;
    EXPECT_EQ(metric(page, vmc_series("sweepd_vmc_frames_total", stream)), kFramesEach) << stream;
    EXPECT_EQ(metric(page, vmc_series("sweepd_vmc_bones_total", stream)),
              static_cast<double>(kFramesEach * performer.sent_bones[0].size()))
        << stream;
    EXPECT_EQ(metric(page, vmc_series("sweepd_vmc_senders", stream)), 1.0) << stream;
    EXPECT_EQ(metric(page, vmc_series("sweepd_vmc_subscribers", stream)), 1.0) << stream;
  }
}

// SubscribeStream names the streams there are when asked for another.
TEST(DaemonVmcStreams, ASubscriptionToAStreamNoReceiverHasNamesTheStreams) {
  ScratchDirectory directory("vmc_streams_names");
  DaemonProcess daemon(directory.path(), {"--vmc-listen", "127.0.0.1:0=alice", "--vmc-listen",
                                          "127.0.0.1:0=bob", "--mannequin-vertices", "1000"});
  ASSERT_TRUE(daemon.running()) << daemon.log();
  std::unique_ptr<client::Connection> subscriber =
      open_connection("127.0.0.1:" + std::to_string(daemon.port()), pb::PoseDelivery::LatestWins);
  try {
    subscribe_to_stream(*subscriber, "mannequin");
    ADD_FAILURE() << "subscribed to a stream no receiver has";
  } catch (const client::ServerError& error) {
    EXPECT_EQ(std::string(error.what()),
              "server error InvalidArgument: SubscribeStream: no stream named 'mannequin' (this "
              "server's streams: 'alice', 'bob')");
  }
}

}  // namespace
}  // namespace sweepd::test
