// One name per model (issue 48 item 5): a model uploaded from a client's file is held under the
// file's base name, never the client's local path — by the C++ clients (stream_poses,
// render_frames, sweepctl --server: client::model_name_of_file), by the server for a client
// that still sends a path (server::upload_name), and after a restart — and every client prints
// the name the server holds. An UnknownModel error names the models the server holds.
#include <gtest/gtest.h>

#include <csignal>
#include <string>
#include <vector>

#include "client/connection.h"
#include "client/model_source.h"
#include "io/gltf/gltf_save.h"
#include "mannequin/mannequin.h"
#include "protocol/messages.h"
#include "server/models/model_service.h"
#include "tests/server/client_run.h"
#include "tests/server/daemon_process.h"

namespace sweepd::test::model_names_test {
namespace {

const fs::path kClip = fs::path(SWEEPD_SHARED_DATA) / "motion/cmu_01_01.bvh";

// Each of the three: the name a path gets, on the client and on the server.
TEST(ModelNames, AFilesBaseNameOnTheClientAndOnTheServer) {
  EXPECT_EQ(client::model_name_of_file("/home/me/scans/body_scan.glb"), "body_scan");
  EXPECT_EQ(client::model_name_of_file("body.fbx"), "body");
  EXPECT_EQ(server::upload_name("/home/me/scans/body_scan.glb"), "body_scan");
  EXPECT_EQ(server::upload_name("C:\\scans\\Body.GLTF"), "Body");
  EXPECT_EQ(server::upload_name("body.dae"), "body");
  // A name a user gives stays as given: only a model file's extension is dropped.
  EXPECT_EQ(server::upload_name("body.v2"), "body.v2");
  EXPECT_EQ(server::upload_name("mannequin"), "mannequin");
}

struct Held {
  std::uint32_t id = 0;
  std::string name;
};

Held load(const DaemonProcess& daemon, client::ModelSource& source) {
  client::Connection connection("127.0.0.1:" + std::to_string(daemon.port()));
  connection.hello("", "model_names_test");
  const protocol::ModelInfo& info = source.load(connection);
  return {info.model_id(), info.name()->str()};
}

// The error a LoadModel by name gets, or "" when it loads.
std::string load_error(const DaemonProcess& daemon, const std::string& name) {
  client::ModelSource source(name, {});
  try {
    load(daemon, source);
  } catch (const client::ServerError& error) {
    return error.what();
  }
  return "";
}

TEST(ModelNames, AnUploadIsHeldUnderItsFilesBaseNameByEveryClientAndAfterARestart) {
  if (!fs::exists(kClip)) GTEST_SKIP() << "shared data absent: " << kClip;
  const fs::path directory = fresh_directory("model_names");
  fs::create_directories(directory / "scans");
  const fs::path file = fs::absolute(directory / "scans" / "body_scan.glb");
  io::save_gltf(mannequin::make_mannequin({.target_vertices = 2000}), file);
  Held held;
  {
    DaemonProcess daemon(directory, {"--mannequin-vertices", "1000"});
    ASSERT_TRUE(daemon.running()) << daemon.log();
    // A client that still sends its local path: the server holds the file's base name.
    client::ModelSource old_client(file.string(), read_bytes(file));
    held = load(daemon, old_client);
    EXPECT_EQ(held.name, "body_scan");

    // stream_poses and sweepctl name the upload so, and print the name the server holds.
    const std::string port = std::to_string(daemon.port());
    const ClientRun streamed =
        run_client(std::string(SWEEPD_STREAM_POSES) + " --port " + port + " --bvh " +
                   kClip.string() + " --model-file " + file.string() + " --frames 3 --flat-out");
    ASSERT_EQ(streamed.exit_code, 0) << streamed.output << daemon.log();
    EXPECT_NE(streamed.output.find("model 'body_scan' (id " + std::to_string(held.id) + ")"),
              std::string::npos)
        << streamed.output;
    EXPECT_EQ(streamed.output.find(file.string()), std::string::npos) << streamed.output;
    const ClientRun posed =
        run_client(std::string(SWEEPD_SWEEPCTL) + " --server 127.0.0.1:" + port + " pose " +
                   file.string() + " -o " + (directory / "posed.glb").string());
    ASSERT_EQ(posed.exit_code, 0) << posed.output << daemon.log();
    EXPECT_NE(posed.output.find("model 'body_scan' (id " + std::to_string(held.id) +
                                ") on sweepd at 127.0.0.1:" + port + " (already loaded)"),
              std::string::npos)
        << posed.output;
    // A name the user gives is the name held (other bytes: the same bytes keep their name).
    const ClientRun named = run_client(
        std::string(SWEEPD_STREAM_POSES) + " --port " + port + " --bvh " + kClip.string() +
        " --model-file " + (directory / "posed.glb").string() + " --model posed_body --frames 1");
    ASSERT_EQ(named.exit_code, 0) << named.output << daemon.log();
    EXPECT_NE(named.output.find("model 'posed_body' (id "), std::string::npos) << named.output;
    daemon.signal(SIGTERM);
    ASSERT_TRUE(daemon.wait().has_value());
  }
  // After a restart, a client that has no file finds the model by that name.
  DaemonProcess restarted(directory, {"--mannequin-vertices", "1000"});
  ASSERT_TRUE(restarted.running()) << restarted.log();
  client::ModelSource by_name("body_scan", {});
  const Held found = load(restarted, by_name);
  EXPECT_EQ(found.id, held.id);
  EXPECT_EQ(found.name, "body_scan");
}

// UnknownModel names the models held, so a client sees which names exist: by name (LoadModel)
// and by id (a pose). Capped at 12 names (motion/name_list.h, tested there).
TEST(ModelNames, UnknownModelNamesTheModelsTheServerHolds) {
  const fs::path directory = fresh_directory("model_names_unknown");
  DaemonProcess daemon(directory, {"--mannequin-vertices", "1000"});
  ASSERT_TRUE(daemon.running()) << daemon.log();
  const std::string mannequin =
      "'mannequin' (id " + std::to_string(daemon.model_id("mannequin")) + ")";
  const std::string by_name = load_error(daemon, "mannequn");  // a typo
  EXPECT_NE(by_name.find("UnknownModel"), std::string::npos) << by_name;
  EXPECT_NE(by_name.find("model 'mannequn'"), std::string::npos) << by_name;
  EXPECT_NE(by_name.find("this server holds " + mannequin), std::string::npos) << by_name;

  client::Connection connection("127.0.0.1:" + std::to_string(daemon.port()));
  connection.hello("", "model_names_test");
  const std::uint32_t absent = daemon.model_id("mannequin") + 1;
  flatbuffers::FlatBufferBuilder& builder = connection.builder();
  builder.Clear();
  protocol::PoseFields fields;
  fields.model_id = absent;
  fields.sequence = 7;
  connection.send(protocol::finish_message(builder, protocol::add_pose(builder, fields)));
  try {
    connection.expect<protocol::PosedVertices>();
    ADD_FAILURE() << "a pose of model " << absent << " was answered";
  } catch (const client::ServerError& error) {
    EXPECT_EQ(error.code(), protocol::ErrorCode::UnknownModel);
    const std::string message = error.what();
    EXPECT_NE(message.find("no model with id " + std::to_string(absent) + " (this server holds " +
                           mannequin + ")"),
              std::string::npos)
        << message;
  }
}

}  // namespace
}  // namespace sweepd::test::model_names_test
