// sweepd's setup pieces without a process: flags and the JSON config file, and the token
// comparison.
#include "server/config.h"

#include <gtest/gtest.h>

#include <fstream>

#include "server/transport/constant_time_equal.h"
#include "tests/server/daemon_process.h"

namespace sweepd::test {
namespace {

using server::ConfigError;
using server::parse_server_config;

server::ServerConfig parse(std::vector<std::string_view> args) { return parse_server_config(args); }

std::string error_of(std::vector<std::string_view> args) {
  try {
    parse(args);
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "";
}

TEST(ServerConfig, FlagsSetTheirFieldsAndDefaultsStay) {
  const server::ServerConfig config =
      parse({"--port", "0", "--token", "abc", "--max-poses-in-flight", "3", "--store-dir", "/x"});
  EXPECT_EQ(config.port, 0);
  EXPECT_EQ(config.token, "abc");
  EXPECT_EQ(config.max_poses_in_flight, 3u);
  EXPECT_EQ(config.store_dir, "/x");
  EXPECT_EQ(config.max_frame_bytes, 64u << 20);  // untouched default
}

TEST(ServerConfig, ConfigFileIsReadAndFlagsOverrideIt) {
  const fs::path directory = fresh_directory("config");
  const fs::path file = directory / "sweepd.json";
  std::ofstream(file) << R"({"port": 9000, "token": "from-file", "max_models": 5})";
  const server::ServerConfig config = parse({"--token", "flag", "--config", file.c_str()});
  EXPECT_EQ(config.port, 9000);
  EXPECT_EQ(config.token, "flag");
  EXPECT_EQ(config.max_models, 5u);
  fs::remove_all(directory);
}

TEST(ServerConfig, ConfigFileMayCarryComments) {
  const fs::path directory = fresh_directory("commented_config");
  const fs::path file = directory / "sweepd.conf";
  std::ofstream(file) << "// the port\n{\n  \"port\": 9001, /* inline */ \"max_models\": 4\n}\n";
  const server::ServerConfig config = parse({"--config", file.c_str()});
  EXPECT_EQ(config.port, 9001);
  EXPECT_EQ(config.max_models, 4u);
  fs::remove_all(directory);
}

// deploy/sweepd.conf, the systemd unit's config file, as the unit passes it (flags after it).
TEST(ServerConfig, TheSystemdUnitsConfigFileIsValid) {
  const std::string file = std::string(SWEEPD_SOURCE_DIR) + "/deploy/sweepd.conf";
  const server::ServerConfig config = parse({"--config", file, "--store-dir", "/var/lib/sweepd"});
  EXPECT_EQ(config.listen_address, "0.0.0.0");
  EXPECT_EQ(config.port, 7878);
  EXPECT_EQ(config.http_address, "0.0.0.0");
  EXPECT_EQ(config.http_port, 9464);
  EXPECT_EQ(config.store_dir, "/var/lib/sweepd");
  EXPECT_TRUE(config.token.empty());  // the token comes from the credential, not the file
}

TEST(ServerConfig, ClipLimitsAreFlagsAndConfigKeys) {
  EXPECT_EQ(parse({}).max_clips, 64u);
  EXPECT_EQ(parse({}).max_clip_bytes, 256ull << 20);
  const server::ServerConfig flags = parse({"--max-clips", "3", "--max-clip-bytes", "1000"});
  EXPECT_EQ(flags.max_clips, 3u);
  EXPECT_EQ(flags.max_clip_bytes, 1000u);
  const std::string file = std::string(SWEEPD_SOURCE_DIR) + "/deploy/sweepd.conf";
  EXPECT_EQ(parse({"--config", file}).max_clips, 64u);
}

TEST(ServerConfig, WorkerSpinIsOffByDefaultAndAFlagAndAConfigKey) {
  EXPECT_EQ(parse({}).worker_spin_us, 0);
  EXPECT_EQ(parse({"--worker-spin-us", "200"}).worker_spin_us, 200);
  const std::string file = std::string(SWEEPD_SOURCE_DIR) + "/deploy/sweepd.conf";
  EXPECT_EQ(parse({"--config", file}).worker_spin_us, 0);
  EXPECT_NE(error_of({"--worker-spin-us", "-1"}).find("out of range"), std::string::npos);
  EXPECT_NE(error_of({"--worker-spin-us", "100001"}).find("out of range"), std::string::npos);
}

TEST(ServerConfig, MistakesAreNamed) {
  EXPECT_NE(error_of({"--prot", "1"}).find("--prot: unknown flag"), std::string::npos);
  EXPECT_NE(error_of({"--port"}).find("--port: missing value"), std::string::npos);
  EXPECT_NE(error_of({"--port", "80x"}).find("'80x' is not an integer"), std::string::npos);
  EXPECT_NE(error_of({"--port", "70000"}).find("out of range"), std::string::npos);
  EXPECT_NE(error_of({"--config", "/nonexistent/sweepd.json"}).find("/nonexistent/sweepd.json"),
            std::string::npos);
  const fs::path directory = fresh_directory("bad_config");
  std::ofstream(directory / "bad.json") << R"({"port": 1, "colour": "red"})";
  EXPECT_NE(error_of({"--config", (directory / "bad.json").c_str()}).find("'colour': unknown key"),
            std::string::npos);
  fs::remove_all(directory);
}

TEST(ServerConfig, CollisionBackendIsAFlagAndAConfigKey) {
  EXPECT_EQ(parse({}).collision, gpu::CollisionChoice::kAuto);
  EXPECT_EQ(parse({"--collision", "gpu"}).collision, gpu::CollisionChoice::kGpu);
  const fs::path directory = fresh_directory("collision_config");
  const fs::path file = directory / "sweepd.json";
  std::ofstream(file) << R"({"collision": "cpu"})";
  EXPECT_EQ(parse({"--config", file.c_str()}).collision, gpu::CollisionChoice::kCpu);
  EXPECT_EQ(parse({"--config", file.c_str(), "--collision", "auto"}).collision,
            gpu::CollisionChoice::kAuto);  // the flag wins
  EXPECT_NE(error_of({"--collision", "cuda"}).find("--collision: 'cuda' is not auto, gpu or cpu"),
            std::string::npos);
  fs::remove_all(directory);
}

TEST(ServerConfig, HttpSidePortIsOffByDefaultAndNeverTheProtocolPort) {
  EXPECT_EQ(parse({}).http_port, -1);
  const server::ServerConfig v4 = parse({"--http-listen", "0.0.0.0:9464"});
  EXPECT_EQ(v4.http_address, "0.0.0.0");
  EXPECT_EQ(v4.http_port, 9464);
  const server::ServerConfig v6 = parse({"--http-listen", "[::1]:0", "--port", "0"});
  EXPECT_EQ(v6.http_address, "::1");
  EXPECT_EQ(v6.http_port, 0);
  EXPECT_NE(error_of({"--http-listen", "127.0.0.1:7878"}).find("is the protocol port"),
            std::string::npos);  // 7878: the default protocol port
  EXPECT_NE(error_of({"--http-listen", "9464"}).find("is not ADDR:PORT"), std::string::npos);
  EXPECT_NE(error_of({"--http-listen", "h:99999"}).find("out of range"), std::string::npos);
}

TEST(ServerConfig, ViewerDirIsServedOnlyWithTheHttpSidePort) {
  EXPECT_TRUE(parse({}).viewer_dir.empty());
  EXPECT_EQ(parse({"--http-listen", "127.0.0.1:0", "--viewer-dir", "web"}).viewer_dir, "web");
  EXPECT_NE(error_of({"--viewer-dir", "web"}).find("--viewer-dir: needs --http-listen"),
            std::string::npos);
}

TEST(ServerConfig, WebSocketListenerIsOffByDefaultAndKeepsTheTokenOffPlainNetworks) {
  EXPECT_EQ(parse({}).ws_port, -1);
  const server::ServerConfig config = parse(
      {"--ws-listen", "[::1]:7879", "--ws-port-file", "ws_port", "--ws-allowed-origin",
       "https://a.example,https://b.example", "--ws-allowed-origin", "http://c.example:8080"});
  EXPECT_EQ(config.ws_address, "::1");
  EXPECT_EQ(config.ws_port, 7879);
  EXPECT_EQ(config.ws_port_file, "ws_port");
  EXPECT_EQ(config.ws_allowed_origins,
            (std::vector<std::string>{"https://a.example", "https://b.example",
                                      "http://c.example:8080"}));
  EXPECT_NE(error_of({"--ws-listen", "127.0.0.1:7878"}).find("already the protocol or HTTP"),
            std::string::npos);
  const std::string error = error_of({"--ws-listen", "0.0.0.0:7879", "--token", "t"});
  for (const char* named :
       {"plain WebSocket on 0.0.0.0", "--tls-cert", "--ws-listen 127.0.0.1", "--allow-plaintext"}) {
    EXPECT_NE(error.find(named), std::string::npos) << named << " in: " << error;
  }
  EXPECT_EQ(error_of({"--ws-listen", "0.0.0.0:7879", "--token", "t", "--tls-cert", "c", "--tls-key",
                      "k"}),
            "");
  EXPECT_EQ(error_of({"--ws-listen", "127.0.0.1:7879", "--token", "t"}), "");
}

TEST(ServerConfig, VmcReceiverIsOffByDefaultAndTakesAnAddressWithOrWithoutAPort) {
  EXPECT_TRUE(parse({}).vmc_listens.empty());
  EXPECT_EQ(parse({}).vmc_model, "mannequin");
  const auto listens = [](std::string_view value) {
    const server::ServerConfig config = parse({"--vmc-listen", value});
    EXPECT_EQ(config.vmc_listens.size(), 1u);
    const server::VmcListen& listen = config.vmc_listens.at(0);
    return listen.address + " " + std::to_string(listen.port) + " " + listen.model;
  };
  EXPECT_EQ(listens("127.0.0.1"), "127.0.0.1 39539 mannequin")
      << "VMC's receiver port when left out, --vmc-model's default model";
  EXPECT_EQ(listens("0.0.0.0:0"), "0.0.0.0 0 mannequin");
  EXPECT_EQ(listens("[::1]:40000"), "::1 40000 mannequin");
  EXPECT_EQ(listens("[::1]"), "::1 39539 mannequin");
  EXPECT_EQ(listens("::1"), "::1 39539 mannequin") << "a bare IPv6 address has no port";
  EXPECT_EQ(listens("127.0.0.1=alice"), "127.0.0.1 39539 alice");
  EXPECT_EQ(listens("[::1]:40000=alice"), "::1 40000 alice");
  EXPECT_EQ(listens("::1=alice"), "::1 39539 alice");
  const server::ServerConfig config =
      parse({"--vmc-listen", "127.0.0.1", "--vmc-port-file", "vmc_port", "--vmc-model", "body"});
  EXPECT_EQ(config.vmc_port_file, "vmc_port");
  EXPECT_EQ(config.vmc_model, "body");
  EXPECT_EQ(config.vmc_listens.at(0).model, "body") << "--vmc-model applies wherever it stands";
  EXPECT_EQ(error_of({"--vmc-listen", "127.0.0.1:70000"}),
            "--vmc-listen: 70000 is out of range [0, 65535]");
  EXPECT_EQ(error_of({"--vmc-listen", ":39539"}), "--vmc-listen: ':39539' names no address");
  EXPECT_EQ(error_of({"--vmc-listen", "[::1]39539"}),
            "--vmc-listen: '[::1]39539' is not ADDR[:PORT][=MODEL]");
  EXPECT_EQ(error_of({"--vmc-listen", "127.0.0.1:39539="}),
            "--vmc-listen: '127.0.0.1:39539=' names no model after '='");
}

// A receiver (a port) per model, as a VMC receiving app listens on a port per avatar: the
// streams are named by their models, so no two receivers pose one model or share one port.
TEST(ServerConfig, EachVmcReceiverPosesItsOwnModel) {
  const server::ServerConfig config =
      parse({"--vmc-listen", "127.0.0.1:39539=alice", "--vmc-listen", "127.0.0.1:39540",
             "--vmc-listen", "[::1]:0=carol,[::1]:0=dave", "--vmc-model", "bob"});
  const std::vector<server::VmcListen> expected = {{"127.0.0.1", 39539, "alice"},
                                                   {"127.0.0.1", 39540, "bob"},
                                                   {"::1", 0, "carol"},
                                                   {"::1", 0, "dave"}};
  EXPECT_EQ(config.vmc_listens, expected) << "repeatable, or a comma-separated list";
  EXPECT_EQ(error_of({"--vmc-listen", "127.0.0.1:39539", "--vmc-listen", "127.0.0.1:39540"}),
            "--vmc-listen 127.0.0.1:39540=mannequin: the model 'mannequin' is posed by "
            "--vmc-listen 127.0.0.1:39539=mannequin already; a stream is named by its model, one "
            "receiver each");
  EXPECT_EQ(error_of({"--vmc-listen", "[::1]:39539=a", "--vmc-listen", "[::1]:39539=b"}),
            "--vmc-listen [::1]:39539=b: the same address and port as --vmc-listen [::1]:39539=a; "
            "each receiver needs its own port");
  EXPECT_EQ(error_of({"--vmc-listen", "127.0.0.1:0=a", "--vmc-listen", "127.0.0.1:0=b"}), "")
      << "port 0: each picks a free one";
  const fs::path directory = fresh_directory("vmc_config");
  const fs::path file = directory / "sweepd.json";
  std::ofstream(file) << R"({"vmc_listen": "127.0.0.1:39539=alice,127.0.0.1:39540=bob"})";
  const server::ServerConfig from_file =
      parse({"--config", file.c_str(), "--vmc-listen", "127.0.0.1:39541=carol"});
  ASSERT_EQ(from_file.vmc_listens.size(), 3u) << "the file's receivers, then the flag's";
  EXPECT_EQ(from_file.vmc_listens[1].model, "bob");
  EXPECT_EQ(from_file.vmc_listens[2].model, "carol");
}

TEST(ServerConfig, TlsFlagsGoTogetherAndAreConfigKeys) {
  EXPECT_NE(error_of({"--tls-cert", "c.pem"}).find("--tls-cert: needs --tls-key"),
            std::string::npos);
  EXPECT_NE(error_of({"--tls-key", "k.pem"}).find("--tls-key: needs --tls-cert"),
            std::string::npos);
  EXPECT_NE(error_of({"--tls-client-ca", "ca.pem"}).find("--tls-client-ca: needs --tls-cert"),
            std::string::npos);
  const fs::path directory = fresh_directory("tls_config");
  const fs::path file = directory / "sweepd.json";
  std::ofstream(file) << R"({"tls_cert": "c.pem", "tls_key": "k.pem", "tls_client_ca": "ca.pem",
                            "allow_plaintext": true})";
  const server::ServerConfig config = parse({"--config", file.c_str()});
  EXPECT_EQ(config.tls_cert, "c.pem");
  EXPECT_EQ(config.tls_key, "k.pem");
  EXPECT_EQ(config.tls_client_ca, "ca.pem");
  EXPECT_TRUE(config.allow_plaintext);
  fs::remove_all(directory);
}

TEST(ServerConfig, ATokenOnPlainTcpBeyondLoopbackNeedsTlsOrAllowPlaintext) {
  const std::string error = error_of({"--listen", "0.0.0.0", "--token", "t"});
  for (const char* named :
       {"--token", "0.0.0.0", "--tls-cert", "--listen 127.0.0.1", "--allow-plaintext"}) {
    EXPECT_NE(error.find(named), std::string::npos) << named << " in: " << error;
  }
  EXPECT_NE(error_of({"--listen", "10.1.2.3", "--token", "t"}), "");
  // Loopback, TLS, no token, no TCP listener, or the operator's word: all accepted.
  EXPECT_EQ(error_of({"--token", "t"}), "");  // 127.0.0.1 by default
  EXPECT_EQ(error_of({"--listen", "::1", "--token", "t"}), "");
  EXPECT_EQ(error_of({"--listen", "127.0.0.5", "--token", "t"}), "");
  EXPECT_EQ(error_of({"--listen", "0.0.0.0", "--token", "t", "--tls-cert", "c", "--tls-key", "k"}),
            "");
  EXPECT_EQ(error_of({"--listen", "0.0.0.0"}), "");
  EXPECT_EQ(error_of({"--listen", "0.0.0.0", "--token", "t", "--port", "-1"}), "");
  EXPECT_TRUE(parse({"--listen", "0.0.0.0", "--token", "t", "--allow-plaintext"}).allow_plaintext);
}

TEST(ConstantTimeEqual, EqualOnlyForTheSameBytes) {
  EXPECT_TRUE(server::constant_time_equal("s3cret", "s3cret"));
  EXPECT_FALSE(server::constant_time_equal("s3cret", "s3creT"));
  EXPECT_FALSE(server::constant_time_equal("s3cret", "s3cre"));  // prefix
  EXPECT_FALSE(server::constant_time_equal("s3cret", std::string_view("s3cret\0", 7)));
  EXPECT_FALSE(server::constant_time_equal("s3cret", ""));
  EXPECT_TRUE(server::constant_time_equal("", ""));
}

}  // namespace
}  // namespace sweepd::test
