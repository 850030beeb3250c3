// client::ModelSource against real daemons: the bytes go to a server once, later connections
// name the model by its content id — answered without an upload by the server that holds it
// and by a replica sharing its store — and a server with a store of its own gets the upload
// again after answering UnknownModel. Every connection gets the same model: same content id,
// same handle, same vertex count.
#include "client/model_source.h"

#include <gtest/gtest.h>

#include "io/gltf/gltf_save.h"
#include "mannequin/mannequin.h"
#include "tests/server/daemon_process.h"

namespace sweepd::test {
namespace {

struct Loaded {
  std::uint32_t id = 0;
  std::string content_id;
  std::uint32_t vertices = 0;
};

Loaded load(client::ModelSource& source, const DaemonProcess& daemon) {
  client::Connection connection("127.0.0.1:" + std::to_string(daemon.port()));
  connection.hello("", "model_source_test");
  const protocol::ModelInfo& info = source.load(connection);
  Loaded loaded{info.model_id(), info.content_id() ? info.content_id()->str() : "",
                info.vertex_count()};
  connection.close();
  return loaded;
}

TEST(ModelSource, UploadsOnceThenNamesTheModelByItsContentId) {
  const fs::path directory = fresh_directory("model_source");
  const fs::path glb = directory / "body.glb";
  io::save_gltf(mannequin::make_mannequin({.target_vertices = 2500}), glb);
  const std::vector<std::string> small = {"--mannequin-vertices", "1000"};
  std::vector<std::string> shared = small, own = small;
  shared.insert(shared.end(), {"--store-dir", (directory / "shared").string()});
  fs::create_directories(directory / "a");
  fs::create_directories(directory / "b");
  fs::create_directories(directory / "c");
  DaemonProcess first(directory / "a", shared), sharing(directory / "b", shared),
      alone(directory / "c", own);
  ASSERT_TRUE(first.running() && sharing.running() && alone.running());

  client::ModelSource source("body", read_bytes(glb));
  const Loaded bound = load(source, first);
  EXPECT_EQ(source.uploads(), 1);
  ASSERT_EQ(bound.content_id.size(), 64u);
  EXPECT_EQ(load(source, first).content_id, bound.content_id);
  EXPECT_EQ(source.uploads(), 1) << "the server holds it: asked by content id, no bytes";
  const Loaded adopted = load(source, sharing);
  EXPECT_EQ(source.uploads(), 1) << "the replica sharing the store adopts it";
  EXPECT_NE(sharing.log().find("\"event\":\"model_adopted\""), std::string::npos) << sharing.log();
  const Loaded uploaded_again = load(source, alone);
  EXPECT_EQ(source.uploads(), 2) << "a store of its own: UnknownModel, then the upload";
  for (const Loaded& other : {adopted, uploaded_again}) {
    EXPECT_EQ(other.id, bound.id);
    EXPECT_EQ(other.content_id, bound.content_id);
    EXPECT_EQ(other.vertices, bound.vertices);
  }
  fs::remove_all(directory);
}

}  // namespace
}  // namespace sweepd::test
