// sweepd with TLS on its TCP listener (--tls-cert, --tls-key, --tls-client-ca), certificates
// made by the test (tests/server/test_certificates.h): poses over TLS equal those over the
// plain Unix socket of the same daemon bit for bit; a missing client certificate, a client that
// trusts another CA, a plaintext client on the TLS port, a client that never handshakes and a
// TLS client on a plain port are each refused with a clear reason on both sides while the
// daemon serves the next client; the rule that keeps a token off plain TCP beyond loopback;
// the C++ and Python stream_poses over TLS.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <ifaddrs.h>
#include <netinet/in.h>

#include <cstring>
#include <fstream>

#include "client/connection.h"
#include "tests/server/client_run.h"
#include "tests/server/daemon_process.h"
#include "tests/server/pose_frames.h"
#include "tests/server/test_certificates.h"

namespace sweepd::test::daemon_tls_test {
namespace {

constexpr char kToken[] = "tls-t0k";
// A small default model: the tests are about the channel, not the deformation.
const std::vector<std::string> kSmallModel = {"--mannequin-vertices", "2000"};

// The message of what `attempt` throws, or "" when it does not.
template <typename Attempt>
std::string failure_of(Attempt attempt) {
  try {
    attempt();
  } catch (const std::exception& error) {
    return error.what();
  }
  return "";
}

class DaemonTls : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    directory_ = new fs::path(fresh_directory("tls"));
    certificates_ = new std::optional<TestCertificates>(TestCertificates::make(*directory_));
    if (!*certificates_) return;
    const TestCertificates& c = **certificates_;
    // On every address: TLS satisfies the rule that keeps a token off plain TCP, and the
    // certificate check can be tried on 127.0.0.2, a loopback address it does not name.
    daemon_ = new DaemonProcess(
        *directory_,
        with(kSmallModel,
             {"--listen", "0.0.0.0", "--token", kToken, "--tls-cert", c.server_cert.string(),
              "--tls-key", c.server_key.string(), "--tls-client-ca", c.ca.string(), "--unix-socket",
              (*directory_ / "sweepd.sock").string(), "--hello-timeout-ms", "400"}));
  }
  static void TearDownTestSuite() {
    delete daemon_;
    delete certificates_;
    fs::remove_all(*directory_);
    delete directory_;
  }
  void SetUp() override {
    if (!*certificates_) GTEST_SKIP() << "openssl is not installed (deploy/install-deps.sh)";
    ASSERT_TRUE(daemon_->running()) << daemon_->log();
  }

  static client::ClientTls trusted_with_certificate() {
    const TestCertificates& c = **certificates_;
    return {.enabled = true,
            .ca_file = c.ca.string(),
            .cert_file = c.client_cert.string(),
            .key_file = c.client_key.string()};
  }
  static std::string address() { return "127.0.0.1:" + std::to_string(daemon_->port()); }
  // The daemon still serves: a full TLS session with the right certificate.
  static void expect_still_serving() {
    client::Connection connection(address(), trusted_with_certificate());
    EXPECT_GT(connection.hello(kToken, "after").connection_id(), 0u);
    connection.close();
  }

  static fs::path* directory_;
  static std::optional<TestCertificates>* certificates_;
  static DaemonProcess* daemon_;
};
fs::path* DaemonTls::directory_ = nullptr;
std::optional<TestCertificates>* DaemonTls::certificates_ = nullptr;
DaemonProcess* DaemonTls::daemon_ = nullptr;

TEST_F(DaemonTls, PosesOverTlsEqualThoseOverThePlainUnixSocketBitForBit) {
  client::Connection secure(address(), trusted_with_certificate());
  const protocol::Welcome& welcome = secure.hello(kToken, "tls_test");
  EXPECT_GT(welcome.max_poses_in_flight(), 0u);
  const std::size_t joints = secure.load_model("mannequin").joint_names()->size();
  FrameClient plain(*directory_ / "sweepd.sock");
  ASSERT_NE(plain.hello(kToken), nullptr);
  for (std::uint64_t sequence = 1; sequence <= 3; ++sequence) {
    const std::vector<protocol::Quat> wire =
        to_wire(bent_rotations(joints, 0.7f * static_cast<float>(sequence)));
    protocol::PoseFields fields = pose_fields(daemon_->model_id(), sequence, wire);
    fields.normals = true;
    flatbuffers::FlatBufferBuilder& builder = secure.builder();
    builder.Clear();
    secure.send(protocol::finish_message(builder, protocol::add_pose(builder, fields)));
    const protocol::PosedVertices& over_tls = secure.expect<protocol::PosedVertices>();
    const std::vector<float> tls_positions = copy_floats(over_tls.positions_f32());
    const std::vector<float> tls_normals = copy_floats(over_tls.normals_f32());
    ASSERT_TRUE(send_pose(plain, fields));
    const protocol::PosedVertices* over_unix = plain.receive_as<protocol::PosedVertices>();
    ASSERT_NE(over_unix, nullptr);
    const std::vector<float> unix_positions = copy_floats(over_unix->positions_f32());
    ASSERT_GT(tls_positions.size(), 3000u);
    // Bit for bit: TLS carries the same bytes.
    EXPECT_TRUE(same_bits(tls_positions, unix_positions));
    EXPECT_TRUE(same_bits(tls_normals, copy_floats(over_unix->normals_f32())));
  }
  // No descriptor crosses TLS: MapSharedMemory is refused, read through TLS like any reply,
  // and the session goes on.
  try {
    secure.map_shared_memory(4096);
    ADD_FAILURE() << "a shared region over TLS";
  } catch (const client::ServerError& error) {
    EXPECT_EQ(error.code(), protocol::ErrorCode::NotAvailable) << error.what();
  }
  EXPECT_GT(secure.load_model("mannequin").joint_names()->size(), 0u);
  secure.close();
  const std::string log = daemon_->log();
  EXPECT_NE(log.find(R"("client_certificate":"/CN=render-node")"), std::string::npos) << log;
  EXPECT_NE(log.find(R"("version":"TLSv1.3")"), std::string::npos) << log;
}

TEST_F(DaemonTls, AMissingClientCertificateIsRefusedWithAClearReasonOnBothSides) {
  client::ClientTls no_certificate = trusted_with_certificate();
  no_certificate.cert_file.clear();
  no_certificate.key_file.clear();
  // TLS 1.3: the client's side of the handshake completes; the refusal arrives with the
  // first read.
  const std::string failure = failure_of([&] {
    client::Connection connection(address(), no_certificate);
    connection.hello(kToken, "no certificate");
  });
  EXPECT_NE(failure.find("certificate required"), std::string::npos) << failure;
  const std::string log = daemon_->log_with({"peer did not return a certificate"});
  EXPECT_NE(log.find("TLS handshake failed: peer did not return a certificate"), std::string::npos)
      << log;
  expect_still_serving();
}

TEST_F(DaemonTls, AClientTrustingAnotherCaNamesTheCertificateProblem) {
  client::ClientTls other_ca = trusted_with_certificate();
  other_ca.ca_file = (*certificates_)->other_ca.string();
  const std::string failure =
      failure_of([&] { client::Connection connection(address(), other_ca); });
  EXPECT_NE(failure.find("its certificate is not accepted"), std::string::npos) << failure;
  // OpenSSL's verify reason, and the CA file the client trusted.
  EXPECT_NE(failure.find("certificate in certificate chain"), std::string::npos) << failure;
  EXPECT_NE(failure.find("other_ca.pem"), std::string::npos) << failure;
  expect_still_serving();
}

TEST_F(DaemonTls, AServerCertificateForAnotherNameIsRejected) {
  // The certificate names 127.0.0.1 and localhost, not 127.0.0.2 (also loopback on Linux).
  const std::string failure = failure_of([&] {
    client::Connection connection("127.0.0.2:" + std::to_string(daemon_->port()),
                                  trusted_with_certificate());
  });
  EXPECT_NE(failure.find("IP address mismatch"), std::string::npos) << failure;
}

TEST_F(DaemonTls, PlaintextAndSilentClientsAreCutAndTheDaemonServesOthers) {
  FrameClient plaintext(daemon_->port());
  ASSERT_TRUE(plaintext.connected());
  flatbuffers::FlatBufferBuilder builder;
  plaintext.send_bytes(protocol::build_hello(builder, kToken, "plaintext"));
  EXPECT_EQ(plaintext.receive(), nullptr) << "a plaintext Hello gets no reply, only the close";

  const auto opened = std::chrono::steady_clock::now();
  FrameClient silent(daemon_->port());  // opens TCP, never says a word
  EXPECT_TRUE(silent.closed_by_server());
  const double waited_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - opened).count();
  // --hello-timeout-ms 400 bounds the handshake; generous upper bound for a loaded machine.
  EXPECT_GE(waited_ms, 350.0);
  EXPECT_LT(waited_ms, 10000.0);

  const std::string log =
      daemon_->log_with({"wrong version number", "no TLS handshake within 400 ms"});
  EXPECT_NE(log.find("TLS handshake failed: wrong version number"), std::string::npos) << log;
  EXPECT_NE(log.find(R"("reason":"no TLS handshake within 400 ms")"), std::string::npos) << log;
  expect_still_serving();
}

TEST_F(DaemonTls, TheCppAndPythonStreamPosesStreamOverTls) {
  const fs::path clip = fs::path(SWEEPD_SHARED_DATA) / "motion" / "cmu_01_01.bvh";
  if (!fs::exists(clip)) GTEST_SKIP() << "shared data absent: " << clip;
  const TestCertificates& c = **certificates_;
  const std::string common = " --port " + std::to_string(daemon_->port()) + " --token " + kToken +
                             " --bvh " + clip.string() + " --frames 40 --flat-out --tls-ca " +
                             c.ca.string() + " --tls-cert " + c.client_cert.string() +
                             " --tls-key " + c.client_key.string();
  const ClientRun cpp = run_client(std::string(SWEEPD_STREAM_POSES) + common);
  EXPECT_EQ(cpp.exit_code, 0) << cpp.output;
  EXPECT_EQ(pose_counts(cpp.output), (std::array<int, 4>{40, 40, 0, 0})) << cpp.output;
  const ClientRun python = run_client("/usr/bin/python3 " + std::string(SWEEPD_SOURCE_DIR) +
                                      "/client_examples/stream_poses.py" + common);
  EXPECT_EQ(python.exit_code, 0) << python.output;
  EXPECT_EQ(pose_counts(python.output), (std::array<int, 4>{40, 40, 0, 0})) << python.output;
  // Without the client certificate Python names the refusal (exit 3: the connection broke).
  const ClientRun refused = run_client(
      "/usr/bin/python3 " + std::string(SWEEPD_SOURCE_DIR) +
      "/client_examples/stream_poses.py --port " + std::to_string(daemon_->port()) + " --token " +
      kToken + " --bvh " + clip.string() + " --frames 1 --tls-ca " + c.ca.string());
  EXPECT_EQ(refused.exit_code, 3) << refused.output;
  EXPECT_NE(refused.output.find("certificate required"), std::string::npos) << refused.output;
}

TEST_F(DaemonTls, SweepctlAndRenderFramesConnectOverTls) {
  const fs::path clip = fs::path(SWEEPD_SHARED_DATA) / "motion" / "cmu_01_01.bvh";
  if (!fs::exists(clip)) GTEST_SKIP() << "shared data absent: " << clip;
  const TestCertificates& c = **certificates_;
  const std::string server = " --server " + address() + " --token " + kToken + " --tls-ca " +
                             c.ca.string() + " --tls-cert " + c.client_cert.string() +
                             " --tls-key " + c.client_key.string();
  const fs::path out = *directory_ / "out";
  fs::create_directories(out);
  const ClientRun pose =
      run_client(std::string(SWEEPD_SWEEPCTL) + server + " pose mannequin --bvh " + clip.string() +
                 " --frame 10 -o " + (out / "posed.glb").string());
  EXPECT_EQ(pose.exit_code, 0) << pose.output;
  EXPECT_TRUE(fs::exists(out / "posed.glb")) << pose.output;
  const ClientRun render =
      run_client(std::string(SWEEPD_RENDER_FRAMES) + server + " --bvh " + clip.string() +
                 " --frames 0-1 --width 32 --height 32 -o " + (out / "frames").string());
  EXPECT_EQ(render.exit_code, 0) << render.output;
  EXPECT_NE(render.output.find("rendered 2, skipped 0 of 2 frames"), std::string::npos)
      << render.output;
}

TEST(DaemonPlainPort, ATlsClientIsToldItReachedAPlainPortAndTheDaemonStaysUp) {
  const fs::path directory = fresh_directory("tls_to_plain");
  const std::optional<TestCertificates> certificates = TestCertificates::make(directory);
  if (!certificates) GTEST_SKIP() << "openssl is not installed (deploy/install-deps.sh)";
  DaemonProcess daemon(directory, with(kSmallModel, {"--token", kToken}));
  ASSERT_TRUE(daemon.running()) << daemon.log();
  const std::string address = "127.0.0.1:" + std::to_string(daemon.port());
  const std::string failure = failure_of([&] {
    client::ClientTls tls;
    tls.enabled = true;
    tls.ca_file = certificates->ca.string();
    client::Connection connection(address, tls);
  });
  EXPECT_NE(failure.find("TLS handshake with sweepd at " + address), std::string::npos) << failure;
  const std::string log = daemon.log_with({"a TLS handshake on a plain port"});
  EXPECT_NE(log.find("a TLS handshake on a plain port"), std::string::npos) << log;
  client::Connection plain(address);
  EXPECT_GT(plain.hello(kToken, "plain").connection_id(), 0u);
  plain.close();
  fs::remove_all(directory);
}

TEST(DaemonTlsFiles, ACertificateThatWillNotLoadStopsTheStartNamingTheFlagAndFile) {
  const fs::path directory = fresh_directory("tls_files");
  std::ofstream(directory / "not.pem") << "not a certificate\n";
  const std::string files = " --tls-cert " + (directory / "not.pem").string() + " --tls-key " +
                            (directory / "not.pem").string();
  const ClientRun run = run_client(std::string(SWEEPD_DAEMON) + " --port 0 --store-dir " +
                                   (directory / "store").string() + files);
  EXPECT_EQ(run.exit_code, 1) << run.output;  // a start-up failure
  EXPECT_NE(run.output.find("--tls-cert " + (directory / "not.pem").string()), std::string::npos)
      << run.output;
  bool bound = false;  // any binding in the store, named by its content id
  if (fs::exists(directory / "store"))
    for (const fs::directory_entry& entry : fs::directory_iterator(directory / "store"))
      bound = bound || entry.path().extension() == ".sweepbind";
  EXPECT_FALSE(bound) << "stopped before any binding";
  fs::remove_all(directory);
}

// A non-loopback IPv4 address of this machine, or "" when it has none.
std::string non_loopback_address() {
  ifaddrs* interfaces = nullptr;
  if (getifaddrs(&interfaces) != 0) return "";
  std::string found;
  for (ifaddrs* i = interfaces; i != nullptr && found.empty(); i = i->ifa_next) {
    if (i->ifa_addr == nullptr || i->ifa_addr->sa_family != AF_INET) continue;
    const in_addr address = reinterpret_cast<sockaddr_in*>(i->ifa_addr)->sin_addr;
    if ((ntohl(address.s_addr) >> 24) == 127) continue;
    char text[INET_ADDRSTRLEN];
    found = inet_ntop(AF_INET, &address, text, sizeof(text));
  }
  freeifaddrs(interfaces);
  return found;
}

TEST(DaemonTokenInClear, ATokenOnPlainTcpBeyondLoopbackIsRefusedUnlessAllowed) {
  const fs::path directory = fresh_directory("token_in_clear");
  const ClientRun refused =
      run_client(std::string(SWEEPD_DAEMON) + " --port 0 --listen 0.0.0.0 --token " + kToken +
                 " --store-dir " + (directory / "store").string());
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  for (const char* flag : {"--tls-cert", "--listen 127.0.0.1", "--allow-plaintext"}) {
    EXPECT_NE(refused.output.find(flag), std::string::npos) << "the message names " << flag << ":\n"
                                                            << refused.output;
  }
  DaemonProcess allowed(directory, with(kSmallModel, {"--listen", "0.0.0.0", "--token", kToken,
                                                      "--allow-plaintext"}));
  ASSERT_TRUE(allowed.running()) << allowed.log();
  // The client keeps its side of the rule: no token in clear to a host beyond loopback.
  const std::string outside = non_loopback_address();
  if (outside.empty()) GTEST_SKIP() << "this machine has no non-loopback IPv4 address";
  const std::string address = outside + ":" + std::to_string(allowed.port());
  const std::string failure = failure_of([&] {
    client::Connection connection(address);
    connection.hello(kToken, "in clear");
  });
  EXPECT_NE(failure.find("refusing to send the token over plain TCP"), std::string::npos)
      << failure;
  client::ClientTls private_network;
  private_network.allow_plaintext = true;
  client::Connection allowed_client(address, private_network);
  EXPECT_GT(allowed_client.hello(kToken, "private network").connection_id(), 0u);
  allowed_client.close();
  fs::remove_all(directory);
}

}  // namespace
}  // namespace sweepd::test::daemon_tls_test
