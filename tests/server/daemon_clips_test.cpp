// Clips and named joints on the daemon (protocol 1.4, issue 18): a clip uploaded once is posed
// by frame number exactly as `sweepctl pose --bvh --frame` poses it (bit for bit), by time and
// looping; the same text uploads to the same id; rotations keyed by joint names of another
// rig's convention land on the model's joints as its own names do. A model's range of motion
// (1.13, issue 47), asked for without clip bytes, poses as the library's own range of motion
// (bit for bit), and a request for it that is wrong is refused naming the problem.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <map>

#include "cli/served_model.h"
#include "client/clip_upload.h"
#include "client/connection.h"
#include "client/model_source.h"
#include "io/bvh/bvh_load.h"
#include "io/files/file_bytes.h"
#include "io/gltf/gltf_load.h"
#include "io/gltf/gltf_save.h"
#include "io/sweepbind/sweepbind.h"
#include "metrics/quality_metrics.h"
#include "motion/own_skeleton_clip.h"
#include "motion/range_of_motion.h"
#include "tests/motion/misspelt_joint_bvh.h"
#include "tests/server/pose_frames.h"
#include "tests/server/stored_binding.h"
#include "tests/server/sweepctl_remote.h"

namespace sweepd::test {
namespace {

namespace pb = sweepd::protocol;

class DaemonClips : public SweepctlRemote {
 protected:
  void SetUp() override {
    SweepctlRemote::SetUp();
    connection_ = std::make_unique<client::Connection>("127.0.0.1:" + std::to_string(port()));
    connection_->hello(kRemoteTestToken, "daemon_clips_test");
  }
  static std::string clip_text() {
    const std::vector<char> bytes = file_bytes(kClip);
    return {bytes.begin(), bytes.end()};
  }
  // The vertices of `model` posed as the clip's `frame` (and loop, time) on the server; its
  // normals into `normals` when given.
  std::vector<glm::vec3> served_frame(std::uint32_t model, std::size_t vertex_count,
                                      const std::string& clip_id,
                                      std::optional<std::uint32_t> frame,
                                      std::optional<double> seconds = std::nullopt,
                                      bool loop = false,
                                      std::vector<glm::vec3>* normals = nullptr) {
    flatbuffers::FlatBufferBuilder& builder = connection_->builder();
    builder.Clear();
    pb::PoseFields fields;
    fields.model_id = model;
    fields.sequence = ++sequence_;
    fields.normals = normals != nullptr;
    const auto pose = pb::add_pose(builder, fields);
    flatbuffers::Optional<std::uint32_t> wire_frame = flatbuffers::nullopt;
    flatbuffers::Optional<double> wire_seconds = flatbuffers::nullopt;
    if (frame) wire_frame = *frame;
    if (seconds) wire_seconds = *seconds;
    const auto clip =
        pb::CreateClipFrame(builder, builder.CreateString(clip_id), wire_frame, wire_seconds, loop);
    connection_->send(pb::finish_message(builder, pb::CreatePoseFromClip(builder, pose, clip)));
    const pb::PosedVertices& reply = connection_->expect<pb::PosedVertices>();
    EXPECT_EQ(reply.sequence(), sequence_);
    std::vector<glm::vec3> positions(vertex_count);
    EXPECT_TRUE(pb::copy_positions(reply, {&positions[0].x, 3 * positions.size()}));
    if (normals != nullptr) {
      normals->resize(vertex_count);
      EXPECT_TRUE(pb::copy_normals(reply, {&(*normals)[0].x, 3 * normals->size()}));
    }
    return positions;
  }
  std::vector<glm::vec3> served_by_name(std::uint32_t model, std::size_t vertex_count,
                                        const std::vector<std::string>& names,
                                        const std::vector<pb::Quat>& rotations) {
    flatbuffers::FlatBufferBuilder& builder = connection_->builder();
    builder.Clear();
    pb::PoseFields fields;
    fields.model_id = model;
    fields.sequence = ++sequence_;
    const auto pose = pb::add_pose(builder, fields);
    const auto request =
        pb::CreatePoseByName(builder, pose, builder.CreateVectorOfStrings(names),
                             builder.CreateVectorOfStructs(rotations.data(), rotations.size()));
    connection_->send(pb::finish_message(builder, request));
    std::vector<glm::vec3> positions(vertex_count);
    EXPECT_TRUE(pb::copy_positions(connection_->expect<pb::PosedVertices>(),
                                   {&positions[0].x, 3 * positions.size()}));
    return positions;
  }
  static bool same_bits(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0;
  }

  std::unique_ptr<client::Connection> connection_;
  std::uint64_t sequence_ = 0;
};

// Nothing unmapped in silence (issue 48 item 4, protocol 1.12): an upload naming the model it
// will play on gets, in ClipInfo.warnings, the clip joint that matches nothing on it (a
// misspelt joint: tests/motion/misspelt_joint_bvh.h) and the model joints left without motion;
// without a model, the reader's warnings alone (none for this clip); an id the server does not
// hold is a warning naming the models it holds.
TEST_F(DaemonClips, AnUploadNamingItsModelIsToldWhatIsLeftUnmapped) {
  const std::string text = with_misspelt_joint(clip_text());
  ASSERT_FALSE(text.empty());
  const auto warnings_of = [](const pb::ClipInfo& info) {
    std::vector<std::string> warnings;
    if (info.warnings())
      for (const flatbuffers::String* warning : *info.warnings())
        warnings.push_back(warning->str());
    return warnings;
  };
  EXPECT_EQ(warnings_of(client::upload_clip(*connection_, "misspelt.bvh", text, 0.056444f)),
            std::vector<std::string>{});
  const std::uint32_t mannequin = mannequin_id();
  const pb::ClipInfo& info =
      client::upload_clip(*connection_, "misspelt.bvh", text, 0.056444f, {}, mannequin);
  const std::string clip_id = info.clip_id()->str();
  const std::vector<std::string> warnings = warnings_of(info);
  std::string all;
  for (const std::string& warning : warnings) all += warning + "\n";
  // The fingers, the toes, the clip joint that drives nothing, the model joints left still.
  ASSERT_EQ(warnings.size(), 4u) << all;
  EXPECT_EQ(warnings[2],
            "on model 'mannequin': clip joints that drive no model joint (1): HeadTpo; pair them "
            "in a joint name map to drive them");
  EXPECT_TRUE(
      warnings[3].starts_with("on model 'mannequin': model joints the clip leaves "
                              "without motion, at their rest rotation (8): "))
      << warnings[3];
  EXPECT_NE(warnings[3].find("LeftFingerBase"), std::string::npos) << warnings[3];
  // The player built for the warnings serves the frames: a frame of the clip on that model.
  client::ModelSource served("mannequin", {});
  const std::size_t vertices = served.load(*connection_).vertex_count();
  EXPECT_EQ(served_frame(mannequin, vertices, clip_id, 100).size(), vertices);

  const std::uint32_t absent = mannequin + 1;
  const std::vector<std::string> unknown =
      warnings_of(client::upload_clip(*connection_, "misspelt.bvh", text, 0.056444f, {}, absent));
  ASSERT_EQ(unknown.size(), 1u);
  // Other tests of this daemon may have loaded more models: the mannequin is among those named.
  EXPECT_TRUE(unknown[0].starts_with("no model with id " + std::to_string(absent) +
                                     " to play it on (this server holds "))
      << unknown[0];
  EXPECT_NE(unknown[0].find("'mannequin' (id " + std::to_string(mannequin) + ")"),
            std::string::npos)
      << unknown[0];
  EXPECT_TRUE(unknown[0].ends_with("): its joints were not matched")) << unknown[0];
}

TEST_F(DaemonClips, ServerClipFrameEqualsSweepctlPoseBitForBit) {
  const ClientRun local =
      run_sweepctl("pose " + kSharedMale.string() + " --bvh " + kClip.string() + " --frame " +
                   std::to_string(kClipFrame) + " -o " + path("local.glb").string());
  ASSERT_EQ(local.exit_code, 0) << local.output;

  std::ifstream glb_file(kSharedMale, std::ios::binary);
  client::ModelSource male(kSharedMale.filename().string(),
                           {std::istreambuf_iterator<char>(glb_file), {}});
  const pb::ModelInfo& male_info = male.load(*connection_);
  const std::uint32_t model = male_info.model_id();
  // The served model (ModelInfo + MeshRequest), named as sweepctl names a local file's model.
  deform::Model frame_model = cli::served_model(*connection_, male_info);
  frame_model.name = kSharedMale.stem().string();
  const std::string text = clip_text();
  const pb::ClipInfo& info = client::upload_clip(*connection_, "cmu_01_01.bvh", text);
  const motion::Clip clip = io::load_bvh(kClip);
  EXPECT_EQ(info.frame_count(), static_cast<std::uint32_t>(clip.frame_count));
  EXPECT_EQ(info.joint_count(), clip.joints.size());
  EXPECT_FLOAT_EQ(info.frames_per_second(), clip.frames_per_second());
  const std::string clip_id = info.clip_id()->str();
  EXPECT_EQ(clip_id.size(), 64u);
  // Content-addressed: the same text under another name is the same clip; another scale is not.
  EXPECT_EQ(client::upload_clip(*connection_, "again.bvh", text).clip_id()->str(), clip_id);
  EXPECT_NE(client::upload_clip(*connection_, "again.bvh", text, 0.5f).clip_id()->str(), clip_id);

  // The file sweepctl wrote locally is the served model with the served positions and
  // normals, byte for byte (compared as files: a .glb read back does not give every float back
  // as written).
  std::vector<glm::vec3> normals;
  const std::vector<glm::vec3> served = served_frame(model, frame_model.vertex_count(), clip_id,
                                                     kClipFrame, std::nullopt, false, &normals);
  frame_model.positions = served;
  frame_model.normals = normals;
  io::save_gltf(frame_model, path("served.glb"));
  EXPECT_TRUE(file_bytes(path("served.glb")) == file_bytes(path("local.glb")))
      << "the server's retargeting and deformation are sweepctl's: bit for bit";
  EXPECT_GT(metrics::largest_distance(served, io::load_gltf(kSharedMale).positions), 0.1)
      << "frame " << kClipFrame << " is far from the rest pose";

  // Looping wraps frame numbers exactly; a time on frame 300 samples it within float rounding
  // of the frame position (300 * frame_time / frame_time may land a hair before 300, giving a
  // slerp 1 - 1e-5 of the way from frame 299).
  EXPECT_TRUE(same_bits(served_frame(model, served.size(), clip_id,
                                     kClipFrame + static_cast<std::uint32_t>(clip.frame_count),
                                     std::nullopt, /*loop=*/true),
                        served));
  const std::vector<glm::vec3> timed = served_frame(model, served.size(), clip_id, std::nullopt,
                                                    kClipFrame * double{clip.frame_time});
  EXPECT_LT(metrics::largest_distance(timed, served), 1e-4);
}

TEST_F(DaemonClips, RotationsByNameOfAnyConventionLandOnTheModelsJoints) {
  const pb::ModelInfo& info = connection_->load_model("mannequin");
  const std::uint32_t model = info.model_id();
  const std::size_t vertex_count = info.vertex_count();
  std::map<std::string, int> index;
  for (std::uint32_t j = 0; j < info.joint_names()->size(); ++j)
    index[info.joint_names()->Get(j)->str()] = static_cast<int>(j);
  std::vector<pb::Quat> all;  // the rest rotations, some replaced below
  for (const pb::Quat* rest : *info.joint_rest_rotations()) all.push_back(*rest);
  // The mannequin uses CMU/MotionBuilder names; ask in Unreal's and in Mixamo's.
  const std::vector<std::string> own = {"LeftArm", "LeftForeArm", "RightUpLeg", "RightLeg", "Head"};
  const std::vector<std::string> unreal = {"upperarm_l", "lowerarm_l", "thigh_r", "calf_r", "head"};
  const std::vector<std::string> mixamo = {"mixamorig:LeftArm", "mixamorig:LeftForeArm",
                                           "mixamorig:RightUpLeg", "mixamorig:RightLeg",
                                           "mixamorig:Head"};
  const std::vector<pb::Quat> bends = to_wire(bent_rotations(own.size()));
  for (std::size_t i = 0; i < own.size(); ++i) {
    ASSERT_TRUE(index.contains(own[i])) << own[i];
    all[index[own[i]]] = bends[i];
  }
  connection_->builder().Clear();
  connection_->send(pb::finish_message(
      connection_->builder(),
      pb::add_pose(connection_->builder(), pose_fields(model, ++sequence_, all))));
  std::vector<glm::vec3> whole(vertex_count);
  ASSERT_TRUE(pb::copy_positions(connection_->expect<pb::PosedVertices>(),
                                 {&whole[0].x, 3 * whole.size()}));

  EXPECT_TRUE(same_bits(served_by_name(model, vertex_count, own, bends), whole))
      << "named joints at their rotations, the others at rest: the same pose";
  EXPECT_TRUE(same_bits(served_by_name(model, vertex_count, unreal, bends), whole));
  EXPECT_TRUE(same_bits(served_by_name(model, vertex_count, mixamo, bends), whole));
}

TEST_F(DaemonClips, AJointNameMapTravelsWithTheClipAsSweepctlsBvhMap) {
  // The left forearm left unmapped: the clip then does not bend the left elbow.
  const fs::path map = path("forearm_unmapped.json");
  std::ofstream(map) << R"({"LeftForeArm": null})";
  const std::string frame = " --frame " + std::to_string(kClipFrame) + " -o ";
  const std::string clip = " --bvh " + kClip.string();
  const ClientRun local = run_sweepctl("pose " + kSharedMale.string() + clip + " --bvh-map " +
                                       map.string() + frame + path("map_local.glb").string());
  ASSERT_EQ(local.exit_code, 0) << local.output;
  const ClientRun remote =
      run_sweepctl(server() + " pose " + kSharedMale.string() + clip + " --bvh-map " +
                   map.string() + frame + path("map_remote.glb").string());
  ASSERT_EQ(remote.exit_code, 0) << remote.output << log();
  EXPECT_TRUE(file_bytes(path("map_remote.glb")) == file_bytes(path("map_local.glb")))
      << "the server applies the uploaded map as sweepctl applies --bvh-map: bit for bit";
  const ClientRun unmapped = run_sweepctl("pose " + kSharedMale.string() + clip + frame +
                                          path("unmapped_local.glb").string());
  ASSERT_EQ(unmapped.exit_code, 0) << unmapped.output;
  // 1 cm: the left forearm of frame 300 moves far more than that when the elbow bends (the
  // check fails if the map were dropped on the way).
  EXPECT_GT(metrics::largest_distance(io::load_gltf(path("map_local.glb")).positions,
                                      io::load_gltf(path("unmapped_local.glb")).positions),
            0.01);

  // The map is part of the clip's id; a map that is not an object of names is named.
  const std::string text = clip_text();
  const std::string plain = client::upload_clip(*connection_, "a.bvh", text).clip_id()->str();
  EXPECT_NE(client::upload_clip(*connection_, "a.bvh", text, 1.0f, R"({"LeftForeArm": null})")
                .clip_id()
                ->str(),
            plain);
  try {
    client::upload_clip(*connection_, "a.bvh", text, 1.0f, R"({"LeftForeArm": 3})");
    FAIL() << "a number for a joint name was accepted";
  } catch (const client::ServerError& error) {
    EXPECT_EQ(error.code(), pb::ErrorCode::InvalidArgument);
    EXPECT_NE(std::string(error.what()).find("'LeftForeArm': expected a model joint name or null"),
              std::string::npos)
        << error.what();
  }
}

// The range of motion is built by the server from the held model (its skeleton and bound rig
// map): a frame of it is what the library gives for the same frame of motion::range_of_motion,
// played by motion::OwnSkeletonClip on the model's binding as the daemon stored it, bit for bit.
TEST_F(DaemonClips, AModelsRangeOfMotionPosesAsTheLibrarysBitForBit) {
  std::ifstream glb_file(kSharedMale, std::ios::binary);
  client::ModelSource male(kSharedMale.filename().string(),
                           {std::istreambuf_iterator<char>(glb_file), {}});
  const pb::ModelInfo& male_info = male.load(*connection_);
  const std::uint32_t model = male_info.model_id();
  const std::size_t vertex_count = male_info.vertex_count();
  const std::uint32_t joint_count = male_info.joint_names()->size();
  const pb::ClipInfo& info = client::upload_range_of_motion(*connection_, model);
  EXPECT_EQ(info.name()->str(), "range of motion");
  EXPECT_EQ(info.frame_count(), 1441u) << "48 moves of 30 frames, then the rest";
  EXPECT_FLOAT_EQ(info.frames_per_second(), 30.0f);  // 1 / (1/30 s as a float)
  EXPECT_EQ(info.joint_count(), joint_count) << "the model's own joints";
  EXPECT_EQ(info.warnings() ? info.warnings()->size() : 0u, 0u);
  const std::string clip_id = info.clip_id()->str();
  EXPECT_EQ(clip_id.size(), 64u);
  // Named by the model: asked for again, the same clip; another model's is another.
  EXPECT_EQ(client::upload_range_of_motion(*connection_, model).clip_id()->str(), clip_id);
  EXPECT_NE(client::upload_range_of_motion(*connection_, mannequin_id()).clip_id()->str(), clip_id);

  const deform::BoundModel bound = io::load_sweepbind(stored_binding(path("store"), model));
  const motion::RangeOfMotion rom = motion::range_of_motion(bound.model.skeleton, bound.rig);
  ASSERT_FALSE(rom.moves.empty());
  const int peak = rom.moves[0].peak_frame;
  EXPECT_EQ(peak, 15);
  EXPECT_EQ(rom.moves[0].name, "hip flexion 130°");
  const motion::OwnSkeletonClip played(rom.clip, bound.model.skeleton);
  const std::vector<glm::vec3> served =
      served_frame(model, vertex_count, clip_id, static_cast<std::uint32_t>(peak));
  EXPECT_TRUE(same_bits(
      served, library_deformation(bound, played.pose_at_frame(peak), deform::DeformMethod::kSweep)
                  .positions))
      << "the server's range of motion, player and deformation are the library's: bit for bit";
  // Both thighs raised 130°: the knees move by tens of centimetres.
  EXPECT_GT(metrics::largest_distance(served, bound.model.positions), 0.3);
}

TEST_F(DaemonClips, ARangeOfMotionAskedForWronglyIsRefusedNamingTheProblem) {
  // An UploadClip with range_of_motion, optionally a model and BVH text or glTF bytes: the
  // server's error.
  const auto refused = [&](std::optional<std::uint32_t> model, const std::string& bvh,
                           const std::vector<std::uint8_t>& gltf) {
    flatbuffers::FlatBufferBuilder& builder = connection_->builder();
    builder.Clear();
    const auto text = bvh.empty() ? 0 : builder.CreateString(bvh);
    const auto bytes = gltf.empty() ? 0 : builder.CreateVector(gltf);
    connection_->send(pb::finish_message(
        builder,
        pb::CreateUploadClip(
            builder, 0, text, 1.0f, 0, bytes, 0, false,
            model ? flatbuffers::Optional<std::uint32_t>(*model) : flatbuffers::nullopt, true)));
    try {
      connection_->expect<pb::ClipInfo>();
    } catch (const client::ServerError& error) {
      return error;
    }
    ADD_FAILURE() << "held";
    return client::ServerError(pb::ErrorCode::Internal, "");
  };
  const std::uint32_t mannequin = mannequin_id();

  const client::ServerError no_model = refused(std::nullopt, "", {});
  EXPECT_EQ(no_model.code(), pb::ErrorCode::InvalidArgument);
  EXPECT_TRUE(std::string(no_model.what())
                  .ends_with("range of motion: model_id is required: the clip is built from that "
                             "model's skeleton and rig map"))
      << no_model.what();

  const client::ServerError unknown = refused(mannequin + 1, "", {});
  EXPECT_EQ(unknown.code(), pb::ErrorCode::UnknownModel);
  const std::string unknown_message = unknown.what();
  EXPECT_NE(unknown_message.find("range of motion: no model with id " +
                                 std::to_string(mannequin + 1) + " (this server holds "),
            std::string::npos)
      << unknown_message;
  EXPECT_NE(unknown_message.find("'mannequin' (id " + std::to_string(mannequin) + ")"),
            std::string::npos)
      << unknown_message;

  const client::ServerError with_bvh = refused(mannequin, clip_text(), {});
  EXPECT_EQ(with_bvh.code(), pb::ErrorCode::InvalidArgument);
  EXPECT_TRUE(std::string(with_bvh.what())
                  .ends_with("range of motion: the server builds it from the model, but the "
                             "upload also carries bvh: send range_of_motion with model_id alone"))
      << with_bvh.what();
  const std::vector<std::uint8_t> glb = io::read_file_bytes(kSharedMale);
  const client::ServerError with_both = refused(mannequin, "HIERARCHY\n", glb);
  EXPECT_EQ(with_both.code(), pb::ErrorCode::InvalidArgument);
  EXPECT_NE(std::string(with_both.what()).find("also carries bvh, gltf:"), std::string::npos)
      << with_both.what();

  // The connection goes on: the mannequin's range of motion is held.
  EXPECT_GT(client::upload_range_of_motion(*connection_, mannequin).frame_count(), 1u);
}

}  // namespace
}  // namespace sweepd::test
