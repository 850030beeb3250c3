// sweepd's setup pieces without a process: flags and the JSON config file, the token
// comparison, and the model store's restore after a damaged entry.
#include "server/config.h"

#include <gtest/gtest.h>

#include <fstream>

#include "deform/binding/bind.h"
#include "deform/rig/rig_map.h"
#include "mannequin/mannequin.h"
#include "server/models/model_registry.h"
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

TEST(ConstantTimeEqual, EqualOnlyForTheSameBytes) {
  EXPECT_TRUE(server::constant_time_equal("s3cret", "s3cret"));
  EXPECT_FALSE(server::constant_time_equal("s3cret", "s3creT"));
  EXPECT_FALSE(server::constant_time_equal("s3cret", "s3cre"));  // prefix
  EXPECT_FALSE(server::constant_time_equal("s3cret", std::string_view("s3cret\0", 7)));
  EXPECT_FALSE(server::constant_time_equal("s3cret", ""));
  EXPECT_TRUE(server::constant_time_equal("", ""));
}

TEST(ModelRegistry, RestoreKeepsGoodEntriesAndReportsADamagedOne) {
  const fs::path directory = fresh_directory("registry");
  const deform::Model model = mannequin::make_mannequin({.target_vertices = 2000});
  const deform::BoundModel bound = deform::bind(model, deform::detect_rig_map(model.skeleton));
  {
    server::ModelRegistry registry(directory, {}, {});
    registry.add("first", bound, 1);
    registry.add("second", bound, 1);
  }
  // Damage the first model's file: one flipped payload byte fails its checksum.
  {
    std::fstream file(directory / "1.sweepbind", std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(100);
    file.put('\x7f');
  }
  server::ModelRegistry registry(directory, {}, {});
  const std::vector<std::string> problems = registry.restore();
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].find("1.sweepbind"), std::string::npos) << problems[0];
  ASSERT_EQ(registry.models().size(), 1u);
  EXPECT_EQ(registry.models()[0]->name, "second");
  EXPECT_EQ(registry.models()[0]->id, 2u);
  // New ids never reuse an old one, even a dropped one.
  EXPECT_EQ(registry.add("third", bound, 1)->id, 3u);
  EXPECT_EQ(registry.find(std::string_view("third"))->id, 3u);
  fs::remove_all(directory);
}

}  // namespace
}  // namespace sweepd::test
