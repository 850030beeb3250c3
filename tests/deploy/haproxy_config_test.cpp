// deploy/haproxy.cfg: Debian's haproxy accepts it (`haproxy -c`), it says what deploy/README.md
// promises (TCP mode, leastconn, /readyz checks on the side port, slow start), and HAProxy
// started from it on loopback (addresses substituted by tests/server/haproxy_process.h) in front
// of two real sweepd replicas: both checked UP, poses answered through it, leastconn puts two
// clients on two replicas; SIGTERM to one replica: its client gets sweepd's Bye (its stream is
// drained, not cut), HAProxy's check marks it DOWN, and a new client is served by the other.
// Skips, saying so, without haproxy or curl (deploy/install-deps.sh installs both).
#include <gtest/gtest.h>

#include <fstream>

#include "tests/deploy/shell_command.h"
#include "tests/server/daemon_process.h"
#include "tests/server/haproxy_process.h"
#include "tests/server/http_probe.h"
#include "tests/server/pose_frames.h"

namespace sweepd::test {
namespace {

using namespace std::chrono_literals;

const fs::path kConfig = fs::path(SWEEPD_SOURCE_DIR) / "deploy" / "haproxy.cfg";

// The file's directives, comments and blank lines dropped, whitespace collapsed.
std::vector<std::string> directives(const fs::path& file) {
  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) {
    if (const std::size_t hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    std::istringstream words(line);
    std::string collapsed;
    for (std::string word; words >> word;) collapsed += (collapsed.empty() ? "" : " ") + word;
    if (!collapsed.empty()) lines.push_back(collapsed);
  }
  return lines;
}

bool has_directive(const std::vector<std::string>& lines, const std::string& start) {
  return std::any_of(lines.begin(), lines.end(),
                     [&](const std::string& line) { return line.starts_with(start); });
}

TEST(HaproxyConfig, HaproxyAcceptsTheFile) {
  if (!have_haproxy()) GTEST_SKIP() << "haproxy is not installed (deploy/install-deps.sh)";
  const auto [output, code] = run_command("haproxy -c -f " + kConfig.string());
  EXPECT_EQ(code, 0) << output;
  EXPECT_NE(output.find("Configuration file is valid"), std::string::npos) << output;
  EXPECT_EQ(output.find("WARNING"), std::string::npos) << output;
}

TEST(HaproxyConfig, SaysWhatTheReadmePromises) {
  const std::vector<std::string> lines = directives(kConfig);
  EXPECT_TRUE(has_directive(lines, "mode tcp"));
  EXPECT_TRUE(has_directive(lines, "balance leastconn"));
  EXPECT_TRUE(has_directive(lines, "option httpchk"));
  EXPECT_TRUE(has_directive(lines, "http-check send meth GET uri /readyz"));
  EXPECT_TRUE(has_directive(lines, "http-check expect status 200"));
  EXPECT_TRUE(has_directive(lines, "default-server check port 9464 "));
  EXPECT_TRUE(has_directive(lines, "hard-stop-after "));
  const auto server_defaults = std::find_if(lines.begin(), lines.end(), [](const auto& line) {
    return line.starts_with("default-server ");
  });
  ASSERT_NE(server_defaults, lines.end());
  EXPECT_NE(server_defaults->find(" slowstart "), std::string::npos);
  // A draining replica's streams must finish (deploy/haproxy.cfg says why).
  EXPECT_EQ(server_defaults->find("shutdown-sessions"), std::string::npos);
}

// Sends one pose of model `model` (the default mannequin) and returns what came back first.
protocol::Body pose_once(FrameClient& client, std::uint32_t model, std::size_t joints,
                         std::uint64_t sequence) {
  const std::vector<protocol::Quat> wire = to_wire(bent_rotations(joints));
  if (!send_pose(client, pose_fields(model, sequence, wire))) return protocol::Body::NONE;
  const protocol::Message* message = client.receive();
  return message == nullptr ? protocol::Body::NONE : message->body_type();
}

std::size_t mannequin_joints(FrameClient& client) {
  flatbuffers::FlatBufferBuilder builder;
  client.send_bytes(protocol::finish_message(builder, protocol::CreateListModels(builder)));
  const protocol::ModelList* list = client.receive_as<protocol::ModelList>();
  return list == nullptr ? 0 : list->models()->Get(0)->joint_count();
}

class HaproxyInFrontOfTwoReplicas : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!have_haproxy()) GTEST_SKIP() << "haproxy is not installed (deploy/install-deps.sh)";
    if (!have_program("curl")) GTEST_SKIP() << "curl is not installed (deploy/install-deps.sh)";
    directory_ = fresh_directory("haproxy_two_replicas");
    for (int r = 0; r < 2; ++r) {
      const fs::path home = directory_ / ("replica" + std::to_string(r + 1));
      fs::create_directories(home);
      replicas_.push_back(std::make_unique<DaemonProcess>(
          home, std::vector<std::string>{"--http-listen", "127.0.0.1:0", "--http-port-file",
                                         (home / "http_port").string()}));
      ASSERT_TRUE(replicas_.back()->running()) << replicas_.back()->log();
      ports_.push_back({replicas_.back()->port(), std::stoi(read_text(home / "http_port"))});
    }
    // The same default model on both: the same content id, so the same handle on each replica.
    mannequin_ = replicas_[0]->model_id();
    ASSERT_NE(mannequin_, 0u) << replicas_[0]->log();
    ASSERT_EQ(replicas_[1]->model_id(), mannequin_);
    haproxy_ = std::make_unique<HaproxyProcess>(kConfig, directory_, ports_);
    ASSERT_TRUE(haproxy_->running()) << "haproxy did not start; log:\n" << haproxy_->log();
  }
  void TearDown() override {
    haproxy_.reset();
    replicas_.clear();
    if (!directory_.empty()) fs::remove_all(directory_);
  }

  double connections_open(std::size_t replica) {
    return metric(curl_get(ports_[replica].http_port, "/metrics").body, "sweepd_connections_open");
  }

  fs::path directory_;
  std::vector<std::unique_ptr<DaemonProcess>> replicas_;
  std::vector<Replica> ports_;
  std::uint32_t mannequin_ = 0;
  std::unique_ptr<HaproxyProcess> haproxy_;
};

TEST_F(HaproxyInFrontOfTwoReplicas, BalancesByLeastConnectionsAndDrainsAReplicaOnSigterm) {
  // The checks (every 1 s, rise 2) find both replicas' /readyz 200.
  EXPECT_TRUE(haproxy_->wait_for("replica1", "UP", 15s)) << haproxy_->log();
  EXPECT_TRUE(haproxy_->wait_for("replica2", "UP", 15s)) << haproxy_->log();

  FrameClient first(haproxy_->port());
  ASSERT_NE(first.hello(""), nullptr) << haproxy_->log();
  const std::size_t joints = mannequin_joints(first);
  ASSERT_GT(joints, 0u);
  EXPECT_EQ(pose_once(first, mannequin_, joints, 0), protocol::Body::PosedVertices);
  FrameClient second(haproxy_->port());
  ASSERT_NE(second.hello(""), nullptr);
  EXPECT_EQ(pose_once(second, mannequin_, joints, 0), protocol::Body::PosedVertices);
  // leastconn: the second client went to the replica that had none.
  EXPECT_EQ(connections_open(0), 1.0);
  EXPECT_EQ(connections_open(1), 1.0);

  // SIGTERM to replica 1: it drains (its client gets Bye) and exits 0; the check takes it out.
  const auto signalled = std::chrono::steady_clock::now();
  replicas_[0]->signal(SIGTERM);
  EXPECT_EQ(replicas_[0]->wait(), 0) << replicas_[0]->log();
  EXPECT_TRUE(haproxy_->wait_for("replica1", "DOWN", 15s)) << haproxy_->log();
  const double seconds_to_down =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - signalled).count();
  std::printf("replica 1 marked DOWN %.2f s after SIGTERM (inter 1s, fall 2)\n", seconds_to_down);
  EXPECT_EQ(haproxy_->server_states()["replica2"], "UP");

  // The client that was on replica 1 reads Bye (then the end of the stream); the other poses on.
  int byes = 0;
  int answered = 0;
  for (FrameClient* client : {&first, &second}) {
    const protocol::Body body = pose_once(*client, mannequin_, joints, 1);
    byes += body == protocol::Body::Bye;
    answered += body == protocol::Body::PosedVertices;
  }
  EXPECT_EQ(byes, 1);
  EXPECT_EQ(answered, 1);

  // A new client goes to replica 2, the only one UP.
  FrameClient third(haproxy_->port());
  ASSERT_NE(third.hello(""), nullptr) << haproxy_->log();
  EXPECT_EQ(pose_once(third, mannequin_, joints, 0), protocol::Body::PosedVertices);
  EXPECT_EQ(connections_open(1), 2.0);
}

}  // namespace
}  // namespace sweepd::test
