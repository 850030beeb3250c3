// EditKeyEllipse over localhost: the daemon replaces a rest key ellipse (the skin follows it),
// stores the model durably and poses it from then on (also after a restart); bad edits get
// Error replies naming the problem while the connection keeps being served.
#include <gtest/gtest.h>

#include <csignal>

#include "client/connection.h"
#include "io/sweepbind.h"
#include "tests/server/daemon_process.h"
#include "tests/server/pose_frames.h"
#include "tests/server/stored_binding.h"

namespace sweepd::test {
namespace {

namespace pb = sweepd::protocol;

std::vector<glm::vec3> posed(client::Connection& connection, std::uint32_t model_id,
                             const std::vector<glm::quat>& rotations, std::uint64_t sequence) {
  flatbuffers::FlatBufferBuilder& builder = connection.builder();
  builder.Clear();
  const std::vector<pb::Quat> wire = to_wire(rotations);
  connection.send(
      pb::finish_message(builder, pb::add_pose(builder, pose_fields(model_id, sequence, wire))));
  const pb::PosedVertices& reply = connection.expect<pb::PosedVertices>();
  std::vector<glm::vec3> positions(reply.vertex_count());
  EXPECT_TRUE(pb::copy_positions(reply, {&positions[0].x, 3 * positions.size()}));
  return positions;
}

const pb::ModelInfo& edit(client::Connection& connection, std::uint32_t model_id, const char* sweep,
                          std::uint32_t key, float a, float twist) {
  flatbuffers::FlatBufferBuilder& builder = connection.builder();
  builder.Clear();
  const pb::Vec3 offset(0.0f, 0.0f, 0.01f);
  connection.send(pb::finish_message(
      builder,
      pb::CreateEditKeyEllipseDirect(builder, model_id, sweep, key, &offset, a, 0.0f, twist)));
  return connection.expect<pb::ModelInfo>();
}

float largest_distance(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
  float largest = 0.0f;
  for (std::size_t v = 0; v < a.size(); ++v) largest = std::max(largest, glm::distance(a[v], b[v]));
  return largest;
}

TEST(DaemonEditKeyEllipse, AnEditIsPosedStoredAndKeptOverARestart) {
  const ScratchDirectory directory("edit_key");
  std::vector<glm::quat> bent, rest;
  std::vector<glm::vec3> before, after;
  std::uint32_t id = 0;
  {
    DaemonProcess daemon(directory, {"--mannequin-vertices", "4000"});
    ASSERT_TRUE(daemon.running()) << daemon.log();
    client::Connection connection("127.0.0.1", std::to_string(daemon.port()));
    connection.hello("", "edit test");
    const pb::ModelInfo& info = connection.load_model("mannequin");
    id = info.model_id();
    const std::size_t joints = info.joint_names()->size();
    bent = bent_rotations(joints);
    rest.assign(joints, glm::quat(1, 0, 0, 0));
    before = posed(connection, id, bent, 1);
    const std::vector<glm::vec3> rest_before = posed(connection, id, rest, 2);

    // Bad edits: each refused with its reason, nothing changed, the connection goes on.
    const auto refused = [&](std::uint32_t model, const char* sweep, std::uint32_t key, float a,
                             pb::ErrorCode code, const char* reason) {
      try {
        edit(connection, model, sweep, key, a, 0.0f);
        ADD_FAILURE() << "accepted: " << sweep << " " << key;
      } catch (const client::ServerError& error) {
        EXPECT_EQ(error.code(), code) << error.what();
        EXPECT_NE(std::string(error.what()).find(reason), std::string::npos) << error.what();
      }
    };
    refused(id, "tail", 1, 0.05f, pb::ErrorCode::InvalidArgument, "no sweep named 'tail'");
    refused(id, "left_arm", 999, 0.05f, pb::ErrorCode::InvalidArgument, "not 999");
    refused(id, "left_arm", 1, std::nanf(""), pb::ErrorCode::InvalidArgument, "NaN");
    refused(id, "left_arm", 1, -0.05f, pb::ErrorCode::InvalidArgument, "positive");
    refused(id + 41, "left_arm", 1, 0.05f, pb::ErrorCode::UnknownModel, "no model with id");
    EXPECT_EQ(largest_distance(posed(connection, id, bent, 3), before), 0.0f);

    edit(connection, id, "left_arm", 2, 0.07f, 0.3f);
    after = posed(connection, id, bent, 4);
    const std::vector<glm::vec3> rest_after = posed(connection, id, rest, 5);
    // The skin follows the edited key (a 7 cm half-axis, 1 cm along the arm, turned 0.3 rad):
    // the arm moves by centimetres, at rest and bent...
    EXPECT_GT(largest_distance(after, before), 0.005f);
    EXPECT_GT(largest_distance(rest_after, rest_before), 0.005f);
    // ...and only the arm: most of the body keeps its bits.
    std::size_t unchanged = 0;
    for (std::size_t v = 0; v < rest_after.size(); ++v)
      unchanged += rest_after[v] == rest_before[v];
    EXPECT_GT(unchanged, rest_after.size() * 3 / 4);
    // The stored model is the edited one: the library poses it to the daemon's bits.
    const deform::BoundModel stored = io::load_sweepbind(stored_binding(directory / "store", id));
    EXPECT_EQ(largest_distance(
                  library_deformation(stored, bent, deform::DeformMethod::kSweep).positions, after),
              0.0f);
    connection.close();
    daemon.signal(SIGTERM);
    EXPECT_EQ(daemon.wait(), 0);
  }
  DaemonProcess restarted(directory, {"--mannequin-vertices", "4000"});
  ASSERT_TRUE(restarted.running()) << restarted.log();
  client::Connection connection("127.0.0.1", std::to_string(restarted.port()));
  connection.hello("", "edit test");
  EXPECT_EQ(connection.load_model("mannequin").model_id(), id);
  EXPECT_EQ(largest_distance(posed(connection, id, bent, 1), after), 0.0f);
}

}  // namespace
}  // namespace sweepd::test
