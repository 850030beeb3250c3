// EditKeyEllipse over localhost: the daemon replaces a rest key ellipse (the skin follows it),
// stores the model durably and poses it from then on (also after a restart); bad edits get
// Error replies naming the problem while the connection keeps being served. Replicas sharing a
// store: an edit through one is posed by the other from its next request, concurrent edits
// through both are all kept, and a replica on a store of its own is untouched — on the
// procedural mannequin and on the shared MakeHuman male.
#include <gtest/gtest.h>

#include <csignal>
#include <thread>

#include "client/connection.h"
#include "deform/edits/rest_key_edit.h"
#include "io/sweepbind/sweepbind.h"
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

// Three replicas: A and B share one store, C has its own. `upload` empty: the default
// mannequin; else those bytes uploaded as "body" through A, then B and C (B adopts A's).
void expect_shared_store_edits(const fs::path& directory, const std::vector<std::uint8_t>& upload) {
  const fs::path store = directory / "shared_store";
  const std::vector<std::string> flags = {"--mannequin-vertices", "4000"};
  for (const char* replica : {"a", "b", "c"}) fs::create_directories(directory / replica);
  DaemonProcess a(directory / "a", with(flags, {"--store-dir", store.string()}));
  DaemonProcess b(directory / "b", with(flags, {"--store-dir", store.string()}));
  DaemonProcess c(directory / "c", flags);
  ASSERT_TRUE(a.running() && b.running() && c.running()) << a.log() << b.log() << c.log();
  std::vector<std::unique_ptr<client::Connection>> connections;
  std::uint32_t id = 0;
  for (const DaemonProcess* daemon : {&a, &b, &c}) {
    connections.push_back(
        std::make_unique<client::Connection>("127.0.0.1", std::to_string(daemon->port())));
    connections.back()->hello("", "shared edit test");
    const pb::ModelInfo& info = upload.empty() ? connections.back()->load_model("mannequin")
                                               : connections.back()->load_model("body", upload);
    if (id == 0) id = info.model_id();
    EXPECT_EQ(info.model_id(), id) << "one content id, one handle on every replica";
  }
  client::Connection &via_a = *connections[0], &via_b = *connections[1], &via_c = *connections[2];
  const deform::BoundModel original = io::load_sweepbind(stored_binding(store, id));
  const std::vector<glm::quat> bent =
      bent_rotations(static_cast<std::size_t>(original.model.skeleton.joints.size()));
  const std::vector<glm::vec3> before = posed(via_b, id, bent, 1);

  // What the binding becomes after `edits`: the library applies them to the original and poses.
  deform::BoundModel expected = original;
  const auto expect_edit = [&](const char* sweep, std::uint32_t key, float a, float twist) {
    const deform::RestKeyEdit edit{sweep, static_cast<int>(key), {0.0f, 0.0f, 0.01f}, a, 0.0f,
                                   twist};
    ASSERT_EQ(deform::apply_rest_key_edit(expected, edit), "");
  };
  // 1e-6 m: both replicas and the library pose one binding with the same code; any stale copy
  // is centimetres away (the edit moves the arm by more than 5 mm, below).
  constexpr float kSame = 1e-6f;

  edit(via_a, id, "left_arm", 2, 0.07f, 0.3f);
  expect_edit("left_arm", 2, 0.07f, 0.3f);
  const std::vector<glm::vec3> edited_on_a = posed(via_a, id, bent, 2);
  const std::vector<glm::vec3> edited_on_b = posed(via_b, id, bent, 2);
  EXPECT_LE(largest_distance(edited_on_b, edited_on_a), kSame) << "B serves A's edit at once";
  EXPECT_GT(largest_distance(edited_on_b, before), 0.005f) << "and it is not the unedited pose";
  EXPECT_LE(largest_distance(edited_on_a,
                             library_deformation(expected, bent, deform::DeformMethod::kSweep)
                                 .positions),
            kSame);
  EXPECT_EQ(largest_distance(posed(via_c, id, bent, 2), before), 0.0f)
      << "a replica on its own store keeps its model unedited, bit for bit";

  // Edits through A (left arm) and B (right arm) at once, each replica's in its own order:
  // every one is in the store and served by both (an edit that started from a stale copy would
  // undo the other replica's edits).
  constexpr int kEdits = 4;
  const auto value = [](int k) { return 0.05f + 0.01f * static_cast<float>(k); };
  std::thread left([&] {
    for (int k = 0; k < kEdits; ++k) edit(via_a, id, "left_arm", 1 + k % 2, value(k), 0.1f);
  });
  for (int k = 0; k < kEdits; ++k) edit(via_b, id, "right_arm", 1 + k % 2, value(k), -0.1f);
  left.join();
  for (int k = 0; k < kEdits; ++k) {
    expect_edit("left_arm", 1 + k % 2, value(k), 0.1f);
    expect_edit("right_arm", 1 + k % 2, value(k), -0.1f);
  }
  const std::vector<glm::vec3> wanted =
      library_deformation(expected, bent, deform::DeformMethod::kSweep).positions;
  EXPECT_LE(largest_distance(posed(via_a, id, bent, 3), wanted), kSame);
  EXPECT_LE(largest_distance(posed(via_b, id, bent, 3), wanted), kSame);
  EXPECT_LE(largest_distance(library_deformation(io::load_sweepbind(stored_binding(store, id)), bent,
                                                 deform::DeformMethod::kSweep)
                                 .positions,
                             wanted),
            kSame);
  EXPECT_EQ(largest_distance(posed(via_c, id, bent, 3), before), 0.0f);
}

TEST(DaemonEditKeyEllipse, ReplicasSharingAStoreServeEachOthersEditsOnTheMannequin) {
  const ScratchDirectory directory("edit_shared_mannequin");
  expect_shared_store_edits(directory, {});
}

TEST(DaemonEditKeyEllipse, ReplicasSharingAStoreServeEachOthersEditsOnTheSharedMale) {
  const fs::path male = fs::path(SWEEPD_SHARED_DATA) / "models/makehuman_male_cmu.glb";
  if (!fs::exists(male)) GTEST_SKIP() << "shared data absent: " << SWEEPD_SHARED_DATA;
  const ScratchDirectory directory("edit_shared_male");
  expect_shared_store_edits(directory, read_bytes(male));
}

}  // namespace
}  // namespace sweepd::test
