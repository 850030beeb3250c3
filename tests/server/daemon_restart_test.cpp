// sweepd's durability and shutdown: an acknowledged upload survives kill -9 and a restart
// without rebinding; a corrupt store file is quarantined and logged while the other models
// serve; SIGTERM finishes in-flight poses, says Bye and exits 0.
// (Kills at random moments: daemon_crash_safety_test.cpp.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>

#include "io/gltf/gltf_save.h"
#include "io/sweepbind/sweepbind.h"
#include "mannequin/mannequin.h"
#include "tests/deform/rig/legless_cut.h"
#include "tests/server/daemon_process.h"
#include "tests/server/pose_frames.h"
#include "tests/server/stored_binding.h"

namespace sweepd::test {
namespace {

// A small rigged model as a client would upload it: the mannequin written as .glb.
std::vector<std::uint8_t> small_glb(const fs::path& directory) {
  const fs::path file = directory / "small.glb";
  io::save_gltf(mannequin::make_mannequin({.target_vertices = 3000}), file);
  return read_bytes(file);
}

const protocol::ModelInfo* upload(FrameClient& client, const std::string& name,
                                  const std::vector<std::uint8_t>& glb) {
  flatbuffers::FlatBufferBuilder builder;
  client.send_bytes(protocol::finish_message(
      builder, protocol::CreateLoadModelDirect(builder, name.c_str(), &glb), 21));
  return client.receive_as<protocol::ModelInfo>();
}

// The handle a content id gives (server/models/content_id.h): its first 8 hex digits.
std::uint32_t handle_of(const protocol::ModelInfo& info) {
  return static_cast<std::uint32_t>(std::stoul(info.content_id()->str().substr(0, 8), nullptr, 16));
}

// The models listed, by name.
std::vector<std::pair<std::string, std::uint32_t>> list_models(FrameClient& client) {
  flatbuffers::FlatBufferBuilder builder;
  client.send_bytes(protocol::finish_message(builder, protocol::CreateListModels(builder)));
  std::vector<std::pair<std::string, std::uint32_t>> models;
  if (const protocol::ModelList* list = client.receive_as<protocol::ModelList>()) {
    for (const protocol::ModelSummary* m : *list->models()) {
      models.emplace_back(m->name()->str(), m->vertex_count());
    }
  }
  std::sort(models.begin(), models.end());
  return models;
}

TEST(DaemonRestart, AcknowledgedUploadSurvivesKill9WithoutRebinding) {
  const fs::path directory = fresh_directory("kill9");
  const std::vector<std::uint8_t> glb = small_glb(directory);
  std::uint32_t small_id = 0, small_vertices = 0;
  {
    DaemonProcess daemon(directory, {});
    ASSERT_TRUE(daemon.running()) << daemon.log();
    FrameClient client(daemon.port());
    ASSERT_NE(client.hello(""), nullptr);
    const protocol::ModelInfo* info = upload(client, "small", glb);
    ASSERT_NE(info, nullptr);
    small_id = info->model_id();
    small_vertices = info->vertex_count();
    ASSERT_NE(info->content_id(), nullptr);
    EXPECT_EQ(info->content_id()->size(), 64u) << "SHA-256 in hex";
    EXPECT_EQ(small_id, handle_of(*info));
    EXPECT_GT(small_vertices, 2000u);
    daemon.signal(SIGKILL);  // no chance to flush anything after the acknowledgement
    EXPECT_EQ(daemon.wait(), -SIGKILL);
  }
  DaemonProcess restarted(directory, {});
  ASSERT_TRUE(restarted.running()) << restarted.log();
  FrameClient client(restarted.port());
  ASSERT_NE(client.hello(""), nullptr);
  const auto models = list_models(client);
  ASSERT_EQ(models.size(), 2u);
  EXPECT_EQ(models[0].first, "mannequin");
  EXPECT_EQ(models[1], std::make_pair(std::string("small"), small_vertices));
  // The same handle after the restart: it comes from the model's content.
  // Restored from the store, not bound again.
  const std::string log = restarted.log();
  EXPECT_NE(log.find("\"event\":\"model_restored\""), std::string::npos) << log;
  EXPECT_EQ(log.find("\"event\":\"model_loaded\""), std::string::npos) << log;

  // And it poses exactly as the library does with the stored binding.
  const deform::BoundModel bound =
      io::load_sweepbind(stored_binding(directory / "store", small_id));
  const std::vector<glm::quat> rotations = bent_rotations(bound.model.skeleton.joints.size());
  const std::vector<protocol::Quat> wire = to_wire(rotations);
  ASSERT_TRUE(send_pose(client, pose_fields(small_id, 1, wire)));
  const protocol::PosedVertices* reply = client.receive_as<protocol::PosedVertices>();
  ASSERT_NE(reply, nullptr);
  const Deformed library = library_deformation(bound, rotations, deform::DeformMethod::kSweep);
  ASSERT_EQ(reply->positions_f32()->size(), 3 * library.positions.size());
  EXPECT_EQ(std::memcmp(reply->positions_f32()->data(), library.positions.data(),
                        library.positions.size() * sizeof(glm::vec3)),
            0);
  fs::remove_all(directory);
}

TEST(DaemonRestart, ACorruptStoreFileIsQuarantinedLoggedAndTheOtherModelsServe) {
  const fs::path directory = fresh_directory("quarantine");
  const std::vector<std::string> args = {"--mannequin-vertices", "2000"};
  const std::vector<std::uint8_t> glb = small_glb(directory);
  std::uint32_t small_id = 0;
  std::string content_id;
  {
    DaemonProcess daemon(directory, args);
    ASSERT_TRUE(daemon.running()) << daemon.log();
    FrameClient client(daemon.port());
    ASSERT_NE(client.hello(""), nullptr);
    const protocol::ModelInfo* info = upload(client, "small", glb);
    ASSERT_NE(info, nullptr);
    small_id = info->model_id();
    content_id = info->content_id()->str();
    daemon.signal(SIGKILL);
    daemon.wait();
  }
  const fs::path store = directory / "store";
  const fs::path binding = store / (content_id + ".sweepbind");
  std::vector<std::uint8_t> damaged = read_bytes(binding);
  damaged[damaged.size() / 2] ^= 0x01;  // one bit: the checksum fails
  std::ofstream(binding, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(damaged.data()),
             static_cast<std::streamsize>(damaged.size()));
  std::ofstream(store / "index.json.tmp") << "{\"torn";  // what an older sweepd's kill left

  DaemonProcess restarted(directory, args);
  ASSERT_TRUE(restarted.running()) << restarted.log();
  const std::string log = restarted.log();
  EXPECT_NE(log.find("\"event\":\"restore_problem\""), std::string::npos) << log;
  EXPECT_NE(log.find("checksum mismatch"), std::string::npos) << log;
  EXPECT_NE(
      log.find("\"quarantined_to\":\"" + (store / "quarantine" / binding.filename()).string()),
      std::string::npos)
      << log;
  EXPECT_NE(log.find("\"event\":\"store_temporary_removed\""), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(store / "index.json.tmp"));
  // Kept whole beside the store, never deleted.
  std::vector<fs::path> quarantined;
  for (const fs::directory_entry& entry : fs::directory_iterator(store / "quarantine"))
    quarantined.push_back(entry.path().filename());
  std::sort(quarantined.begin(), quarantined.end());
  // The binding, its uploaded source, its label and its self-check's sidecar.
  ASSERT_EQ(quarantined.size(), 4u);
  EXPECT_TRUE(quarantined[0].string().starts_with(content_id + ".glb."));
  EXPECT_TRUE(quarantined[1].string().starts_with(content_id + ".json."));
  EXPECT_TRUE(quarantined[2].string().starts_with(content_id + ".selfcheck.json."));
  EXPECT_TRUE(quarantined[3].string().starts_with(content_id + ".sweepbind."));
  EXPECT_EQ(read_bytes(store / "quarantine" / quarantined[3]), damaged);

  // The other model serves; the same upload binds again, under the same content id and handle.
  FrameClient client(restarted.port());
  ASSERT_NE(client.hello(""), nullptr);
  ASSERT_EQ(list_models(client).size(), 1u);
  const protocol::ModelInfo* mannequin = upload(client, "mannequin", {});
  ASSERT_NE(mannequin, nullptr);
  const std::vector<protocol::Quat> wire =
      to_wire(bent_rotations(mannequin->joint_names()->size()));
  ASSERT_TRUE(send_pose(client, pose_fields(mannequin->model_id(), 1, wire)));
  EXPECT_NE(client.receive_as<protocol::PosedVertices>(), nullptr);
  const protocol::ModelInfo* again = upload(client, "small", glb);
  ASSERT_NE(again, nullptr);
  EXPECT_EQ(again->model_id(), small_id);
  EXPECT_EQ(again->content_id()->str(), content_id);
  fs::remove_all(directory);
}

TEST(DaemonModelDirectory, ListsUnloadedFilesAndLoadsThemByName) {
  const fs::path directory = fresh_directory("model_dir");
  fs::create_directories(directory / "models");
  io::save_gltf(mannequin::make_mannequin({.target_vertices = 3000}),
                directory / "models" / "small.glb");
  DaemonProcess daemon(directory, {"--model-dir", (directory / "models").string()});
  ASSERT_TRUE(daemon.running()) << daemon.log();
  FrameClient client(daemon.port());
  ASSERT_NE(client.hello(""), nullptr);
  // A model directory replaces the default mannequin: only the file, not loaded (0 vertices).
  EXPECT_EQ(list_models(client),
            (std::vector<std::pair<std::string, std::uint32_t>>{{"small.glb", 0}}));

  flatbuffers::FlatBufferBuilder builder;
  client.send_bytes(
      protocol::finish_message(builder, protocol::CreateLoadModelDirect(builder, "small.glb"), 23));
  const protocol::ModelInfo* info = client.receive_as<protocol::ModelInfo>();
  ASSERT_NE(info, nullptr);
  EXPECT_EQ(info->model_id(), handle_of(*info));
  EXPECT_TRUE(info->has_uvs());
  const std::uint32_t vertices = info->vertex_count();
  EXPECT_EQ(list_models(client),
            (std::vector<std::pair<std::string, std::uint32_t>>{{"small.glb", vertices}}));

  builder.Clear();
  client.send_bytes(
      protocol::finish_message(builder, protocol::CreateLoadModelDirect(builder, "absent"), 24));
  const protocol::Error* error = client.receive_as<protocol::Error>();
  ASSERT_NE(error, nullptr);
  EXPECT_EQ(error->code(), protocol::ErrorCode::UnknownModel);
  EXPECT_NE(error->message()->str().find("absent"), std::string::npos);
  fs::remove_all(directory);
}

// A legless upload binds (arms, spine and neck swept) and the daemon logs what it skins instead.
TEST(DaemonModelLoad, ALeglessUploadBindsAndItsRigWarningIsLogged) {
  const fs::path directory = fresh_directory("legless_upload");
  const fs::path file = directory / "bust.glb";
  io::save_gltf(deform::test::legless_cut(mannequin::make_mannequin({.target_vertices = 3000})),
                file);
  DaemonProcess daemon(directory, {"--mannequin-vertices", "1000"});
  ASSERT_TRUE(daemon.running()) << daemon.log();
  FrameClient client(daemon.port());
  ASSERT_NE(client.hello(""), nullptr);
  const protocol::ModelInfo* info = upload(client, "bust", read_bytes(file));
  ASSERT_NE(info, nullptr) << daemon.log();
  EXPECT_GT(info->bind()->sweep_count(), 0u);
  const std::string log = daemon.log();
  EXPECT_NE(log.find("\"event\":\"rig_warning\""), std::string::npos) << log;
  EXPECT_NE(log.find("no legs found"), std::string::npos) << log;
  fs::remove_all(directory);
}

// An uploaded body binds and checks itself (issue 47): each region where the sweep is worse
// than skinning on its range of motion's peaks is logged with both length ratios. The shared
// male loses at the 150° elbow (sweep 5.03x, LBS 3.58x: docs/quality/).
TEST(DaemonModelLoad, AnUploadsSelfCheckWarningsAreLogged) {
  const fs::path male = fs::path(SWEEPD_SHARED_DATA) / "models/makehuman_male_cmu.glb";
  if (!fs::exists(male)) GTEST_SKIP() << "shared data absent";
  const fs::path directory = fresh_directory("self_check_upload");
  DaemonProcess daemon(directory, {"--mannequin-vertices", "1000"});
  ASSERT_TRUE(daemon.running()) << daemon.log();
  FrameClient client(daemon.port());
  ASSERT_NE(client.hello(""), nullptr);
  ASSERT_NE(upload(client, "male", read_bytes(male)), nullptr) << daemon.log();
  const std::string log = daemon.log();
  EXPECT_NE(log.find("\"event\":\"bind_warning\",\"name\":\"male\""), std::string::npos) << log;
  EXPECT_NE(log.find("\"warning\":\"left arm: worse than skinning in "), std::string::npos) << log;
  EXPECT_NE(log.find("(elbow flexion 150°)"), std::string::npos) << log;
  fs::remove_all(directory);
}

TEST(DaemonRestart, ModelLimitIsAnErrorAndTheSessionGoesOn) {
  const fs::path directory = fresh_directory("model_limit");
  DaemonProcess daemon(directory, {"--max-models", "1"});
  ASSERT_TRUE(daemon.running()) << daemon.log();
  FrameClient client(daemon.port());
  ASSERT_NE(client.hello(""), nullptr);
  flatbuffers::FlatBufferBuilder builder;
  const std::vector<std::uint8_t> glb = small_glb(directory);
  client.send_bytes(protocol::finish_message(
      builder, protocol::CreateLoadModelDirect(builder, "small", &glb), 22));
  const protocol::Error* error = client.receive_as<protocol::Error>();
  ASSERT_NE(error, nullptr);
  EXPECT_EQ(error->code(), protocol::ErrorCode::ModelLimit);
  EXPECT_NE(error->message()->str().find("limit of 1"), std::string::npos);
  EXPECT_EQ(list_models(client).size(), 1u);
  fs::remove_all(directory);
}

TEST(DaemonRestart, SigtermAnswersPosesInFlightThenSaysByeAndExitsZero) {
  const fs::path directory = fresh_directory("sigterm");
  DaemonProcess daemon(directory, {"--mannequin-vertices", "60000"});
  ASSERT_TRUE(daemon.running()) << daemon.log();
  FrameClient client(daemon.port());
  ASSERT_NE(client.hello(""), nullptr);
  constexpr std::uint64_t kPoses = 6;
  const std::vector<protocol::Quat> wire = to_wire(bent_rotations(31));
  for (std::uint64_t s = 1; s <= kPoses; ++s) {
    ASSERT_TRUE(send_pose(client, pose_fields(daemon.model_id(), s, wire)));
  }
  ASSERT_NE(client.receive_as<protocol::PosedVertices>(), nullptr);  // work is under way
  daemon.signal(SIGTERM);
  for (std::uint64_t s = 2; s <= kPoses; ++s) {
    const protocol::PosedVertices* reply = client.receive_as<protocol::PosedVertices>();
    ASSERT_NE(reply, nullptr) << "pose " << s << " was not answered";
    EXPECT_EQ(reply->sequence(), s);
  }
  EXPECT_NE(client.receive_as<protocol::Bye>(), nullptr);
  EXPECT_TRUE(client.closed_by_server());
  EXPECT_EQ(daemon.wait(), 0) << daemon.log();
  EXPECT_NE(daemon.log().find("\"reason\":\"SIGTERM\""), std::string::npos);
  fs::remove_all(directory);
}

}  // namespace
}  // namespace sweepd::test
