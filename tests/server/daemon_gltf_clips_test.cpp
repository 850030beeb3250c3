// glTF animation clips on the daemon (protocol 1.7, issues 15 and 18): UploadClip carries a
// .glb's bytes and the animation's name, the server reads it with io::load_gltf_clip from the
// bytes alone and plays it with the motion/ code the local command runs, so
// - `sweepctl --server pose MALE --clip-from BAKED.glb --clip NAME` (retargeted) and
//   `sweepctl --server pose BAKED.glb --clip NAME` (the model's own animation, joint for joint)
//   write the local command's files byte for byte, at a key and between keys;
// - hostile or broken uploads (a truncated GLB, an external URI, an unknown animation name, a
//   file without animations, an animation that drives no joint of the skin, bytes that are no
//   glTF, BVH and glTF at once) are refused naming the problem, and the server goes on serving;
// - the id is the content's: the same bytes and animation give the same id, another animation
//   or own_skeleton another.
// - (1.8) the same baked file written as FBX by assimp plays the same way: its animation stacks,
//   retargeted and on the FBX model's own joints, equal the local command's files byte for byte.
// The clip is made in the test (tests/io/baked_gltf_clip.h: cmu_01_01 retargeted onto the
// shared male, baked as LINEAR, STEP and CUBICSPLINE animations of its own joints).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "client/clip_upload.h"
#include "client/connection.h"
#include "io/files/file_bytes.h"
#include "io/gltf/gltf_load.h"
#include "metrics/quality_metrics.h"
#include "tests/io/baked_gltf_clip.h"
#include "tests/server/sweepctl_remote.h"

namespace sweepd::test {
namespace {

namespace pb = sweepd::protocol;

constexpr int kKeys = 6;

class DaemonGltfClips : public SweepctlRemote {
 protected:
  static void SetUpTestSuite() {
    SweepctlRemote::SetUpTestSuite();
    const deform::Model male = io::load_gltf(kSharedMale);
    io::testing::write_baked_gltf(male, io::testing::bake_cmu_clip(male, kKeys), path("baked.glb"));
    io::testing::write_baked_fbx(path("baked.glb"), path("baked.fbx"));
  }
  void SetUp() override {
    SweepctlRemote::SetUp();
    connection_ = std::make_unique<client::Connection>("127.0.0.1:" + std::to_string(port()));
    connection_->hello(kRemoteTestToken, "daemon_gltf_clips_test");
  }

  // `pose ARGUMENTS` run here and on the daemon: both exit 0 and write the same bytes.
  void expect_remote_equals_local(const std::string& arguments, const std::string& name) {
    const ClientRun local =
        run_sweepctl("pose " + arguments + " -o " + path(name + "_local.glb").string());
    ASSERT_EQ(local.exit_code, 0) << arguments << "\n" << local.output;
    const ClientRun remote = run_sweepctl(server() + " pose " + arguments + " -o " +
                                          path(name + "_remote.glb").string());
    ASSERT_EQ(remote.exit_code, 0) << arguments << "\n" << remote.output << log();
    const std::vector<char> local_bytes = file_bytes(path(name + "_local.glb"));
    EXPECT_GT(local_bytes.size(), 100'000u) << "a whole posed model";
    EXPECT_TRUE(local_bytes == file_bytes(path(name + "_remote.glb")))
        << arguments << ": the server's clip, player and deformation are sweepctl's: bit for bit";
    // The frame is a pose, not the rest: the comparison says something.
    EXPECT_GT(metrics::largest_distance(io::load_gltf(path(name + "_local.glb")).positions,
                                        io::load_gltf(kSharedMale).positions),
              0.02)
        << arguments;
  }

  // The server's error answering the request just sent, or a failure when it answers `Reply`.
  template <typename Reply>
  client::ServerError error_reply(const std::string& what) {
    try {
      connection_->expect<Reply>();
    } catch (const client::ServerError& error) {
      return error;
    }
    ADD_FAILURE() << what;
    return {pb::ErrorCode::Internal, ""};
  }
  // The server's error for an upload of `gltf` (with `animation`).
  client::ServerError refused(const std::vector<std::uint8_t>& gltf, const std::string& animation) {
    flatbuffers::FlatBufferBuilder& builder = connection_->builder();
    builder.Clear();
    connection_->send(pb::finish_message(
        builder,
        pb::CreateUploadClip(builder, builder.CreateString("hostile.glb"), 0, 1.0f, 0,
                             builder.CreateVector(gltf), builder.CreateString(animation))));
    return error_reply<pb::ClipInfo>("the upload was held");
  }
  // An upload refused as ClipLoadFailed with `reason` in its message.
  void expect_clip_refused(const std::vector<std::uint8_t>& gltf, const std::string& animation,
                           const std::string& reason) {
    const client::ServerError error = refused(gltf, animation);
    EXPECT_EQ(error.code(), pb::ErrorCode::ClipLoadFailed) << error.what();
    EXPECT_NE(std::string(error.what()).find(reason), std::string::npos) << error.what();
  }

  static std::vector<std::uint8_t> baked_bytes() { return io::read_file_bytes(path("baked.glb")); }

  std::unique_ptr<client::Connection> connection_;
};

TEST_F(DaemonGltfClips, ServerFramesEqualSweepctlPoseBitForBit) {
  const std::string baked = path("baked.glb").string();
  // Another file's animation retargeted onto the male, at a key (frame 2) and between keys.
  expect_remote_equals_local(
      kSharedMale.string() + " --clip-from " + baked + " --clip cubic " + "--frame 2",
      "retargeted");
  expect_remote_equals_local(
      kSharedMale.string() + " --clip-from " + baked + " --clip linear " + "--time 0.05",
      "retargeted_between");
  // The model's own animation on its own joints: the baked file is the model, uploaded.
  expect_remote_equals_local(baked + " --clip cubic --time 0.05", "own");
  expect_remote_equals_local(baked + " --clip 1 --frame 4", "own_step");
}

TEST_F(DaemonGltfClips, FbxAnimationStacksPlayAsSweepctlPoseBitForBit) {
  client::Connection probe("127.0.0.1:" + std::to_string(port()));
  const pb::Welcome& welcome = probe.hello(kRemoteTestToken, "daemon_gltf_clips_test");
  bool fbx_clips = false;
  for (const auto* capability : *welcome.capabilities())
    fbx_clips = fbx_clips || capability->str() == "fbx_clips";
  EXPECT_TRUE(fbx_clips) << "protocol 1.8's capability";
  const std::string fbx = path("baked.fbx").string();
  expect_remote_equals_local(
      kSharedMale.string() + " --clip-from " + fbx + " --clip linear " + "--time 0.05",
      "fbx_retargeted");
  // The FBX file is the model, uploaded as FBX; its animation plays on its own joints.
  expect_remote_equals_local(fbx + " --clip cubic --frame 3", "fbx_own");
  expect_clip_refused(io::read_file_bytes(path("baked.fbx")), "walk",
                      "no animation named 'walk' (the file's animations: 0 'linear', 1 'step', "
                      "2 'cubic')");
  // An FBX on which libassimp's importer crashes (fuzz/regressions/fbx) is refused naming the
  // crash, and the server goes on: the clip that follows still plays.
  expect_clip_refused(io::read_file_bytes(fs::path(SWEEPD_SOURCE_DIR) /
                                          "fuzz/regressions/fbx/assimp_double_free.fbx"),
                      "0", "the importer crashed on this file");
  expect_remote_equals_local(fbx + " --clip step --frame 2", "fbx_after_crash");
}

TEST_F(DaemonGltfClips, HostileUploadsAreRefusedNamingTheProblemAndTheServerGoesOn) {
  const std::vector<std::uint8_t> bytes = baked_bytes();

  expect_clip_refused({bytes.begin(), bytes.begin() + bytes.size() / 2}, "linear", "truncated");

  // A .gltf whose buffer names a file beside the server: refused before any file is opened.
  const std::string external =
      R"({"asset":{"version":"2.0"},"buffers":[{"uri":"../secret.bin","byteLength":64}]})";
  expect_clip_refused({external.begin(), external.end()}, "0",
                      "external URI \"../secret.bin\" refused");

  expect_clip_refused(bytes, "walk",
                      "no animation named 'walk' (the file's animations: 0 'linear', 1 'step', "
                      "2 'cubic')");

  expect_clip_refused(io::read_file_bytes(kSharedMale), "0", "the file has no animations");

  // An animation whose every channel drives a node that is not one of the skin's joints (the
  // mesh's node).
  tinygltf::Model aimless = io::testing::read_glb(path("baked.glb"));
  int mesh_node = -1;
  for (std::size_t n = 0; n < aimless.nodes.size(); ++n)
    if (aimless.nodes[n].mesh >= 0) mesh_node = static_cast<int>(n);
  ASSERT_GE(mesh_node, 0);
  for (tinygltf::AnimationChannel& channel : aimless.animations[0].channels)
    channel.target_node = mesh_node;
  io::testing::write_glb(aimless, path("aimless.glb"));
  expect_clip_refused(io::read_file_bytes(path("aimless.glb")), "linear",
                      "moves none of the skin's joints");

  const std::string garbage = "this is not a glTF file";
  expect_clip_refused({garbage.begin(), garbage.end()}, "0", "not a valid .gltf");

  // BVH text and glTF bytes in one upload: which clip is meant is unclear.
  flatbuffers::FlatBufferBuilder& builder = connection_->builder();
  builder.Clear();
  const auto both = pb::CreateUploadClip(builder, builder.CreateString("both"),
                                         builder.CreateString("HIERARCHY\n"), 1.0f, 0,
                                         builder.CreateVector(bytes));
  connection_->send(pb::finish_message(builder, both));
  const client::ServerError mixed = error_reply<pb::ClipInfo>("BVH and glTF at once were held");
  EXPECT_EQ(mixed.code(), pb::ErrorCode::InvalidArgument);
  EXPECT_NE(std::string(mixed.what()).find("both BVH text and glTF bytes"), std::string::npos)
      << mixed.what();

  // The server goes on: the whole file uploads, under an id of its content.
  const pb::ClipInfo& info =
      client::upload_gltf_clip(*connection_, "baked.glb", bytes, "cubic", false);
  EXPECT_EQ(info.frame_count(), static_cast<std::uint32_t>(kKeys));  // keys 1/30 s apart
  EXPECT_NEAR(info.frames_per_second(), 30.0f, 1e-3f);  // float keys: 1/30 s within rounding
  const std::string id = info.clip_id()->str();
  EXPECT_EQ(id.size(), 64u);
  EXPECT_EQ(
      client::upload_gltf_clip(*connection_, "renamed.glb", bytes, "cubic", false).clip_id()->str(),
      id);
  EXPECT_NE(
      client::upload_gltf_clip(*connection_, "baked.glb", bytes, "linear", false).clip_id()->str(),
      id);
  EXPECT_NE(
      client::upload_gltf_clip(*connection_, "baked.glb", bytes, "cubic", true).clip_id()->str(),
      id);
}

TEST_F(DaemonGltfClips, AnOwnSkeletonClipOnAnotherSkeletonIsAnInvalidArgument) {
  const std::string id =
      client::upload_gltf_clip(*connection_, "baked.glb", baked_bytes(), "linear", true)
          .clip_id()
          ->str();
  const pb::ModelInfo& mannequin = connection_->load_model("mannequin");
  const std::uint32_t model = mannequin.model_id();
  flatbuffers::FlatBufferBuilder& builder = connection_->builder();
  builder.Clear();
  pb::PoseFields fields;
  fields.model_id = model;
  fields.sequence = 1;
  const auto pose = pb::add_pose(builder, fields);
  const auto frame = pb::CreateClipFrame(builder, builder.CreateString(id), 0u);
  connection_->send(pb::finish_message(builder, pb::CreatePoseFromClip(builder, pose, frame)));
  const client::ServerError error =
      error_reply<pb::PosedVertices>("the male's own animation posed the mannequin");
  EXPECT_EQ(error.code(), pb::ErrorCode::InvalidArgument);
  EXPECT_NE(std::string(error.what()).find("not the model's own skeleton"), std::string::npos)
      << error.what();
}

}  // namespace
}  // namespace sweepd::test
