// ClipStore: clips are named by their content (text and scale), held once however often they
// are uploaded, refused past the count or byte limit with the limit named, and text that is
// not a usable BVH is refused with the reader's reason without taking room. A glTF clip's
// file bytes count against the same byte limit (protocol 1.7; the file is made in the test,
// tests/io/baked_gltf_clip.h), and its players on several models share its frames. A model's
// range of motion (protocol 1.13) is named by the model's content id, built once, and counts its
// keys against the byte limit.
#include "server/models/clip_store.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <memory>
#include <string>

#include "io/files/file_bytes.h"
#include "io/gltf/gltf_load.h"
#include "mannequin/mannequin.h"
#include "motion/range_of_motion.h"
#include "tests/io/baked_gltf_clip.h"

namespace sweepd::server {
namespace {

// Two joints, two frames; `frame_time` tells clips apart.
std::string tiny_clip(const std::string& frame_time = "0.1", int frames = 2) {
  std::string text =
      "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 0\n"
      "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
      "  JOINT Spine\n  {\n    OFFSET 0 1 0\n    CHANNELS 3 Zrotation Xrotation Yrotation\n"
      "    End Site\n    {\n      OFFSET 0 1 0\n    }\n  }\n}\nMOTION\nFrames: " +
      std::to_string(frames) + "\nFrame Time: " + frame_time + "\n";
  for (int f = 0; f < frames; ++f) text += "0 0 0 " + std::to_string(10 * f) + " 0 0 0 0 0\n";
  return text;
}

ClipHandle held(std::variant<ClipHandle, RequestError> outcome) {
  if (const RequestError* error = std::get_if<RequestError>(&outcome)) {
    ADD_FAILURE() << error->message;
    return nullptr;
  }
  return std::get<ClipHandle>(outcome);
}

RequestError refused(std::variant<ClipHandle, RequestError> outcome) {
  EXPECT_TRUE(std::holds_alternative<RequestError>(outcome));
  return std::holds_alternative<RequestError>(outcome) ? std::get<RequestError>(outcome)
                                                       : RequestError{};
}

TEST(ClipStore, TheSameTextIsOneClipWhateverItsNameButAnotherScaleIsAnother) {
  ClipStore store(8, 1 << 20);
  const ClipHandle first = held(store.add("walk.bvh", tiny_clip(), 1.0f));
  ASSERT_NE(first, nullptr);
  EXPECT_EQ(first->id().size(), 64u);
  EXPECT_EQ(first->clip().frame_count, 2);
  EXPECT_EQ(held(store.add("copy.bvh", tiny_clip(), 1.0f)), first);
  EXPECT_EQ(store.find(first->id()), first);
  const ClipHandle scaled = held(store.add("walk.bvh", tiny_clip(), 0.5f));
  ASSERT_NE(scaled, nullptr);
  EXPECT_NE(scaled->id(), first->id());
  EXPECT_FLOAT_EQ(scaled->clip().joints[1].offset.y, 0.5f);  // offsets scaled
  EXPECT_EQ(store.find(std::string(64, '0')), nullptr);
}

TEST(ClipStore, CountLimitRefusesANewClipButNotOneHeld) {
  ClipStore store(2, 1 << 20);
  ASSERT_NE(held(store.add("a", tiny_clip("0.1"), 1.0f)), nullptr);
  ASSERT_NE(held(store.add("b", tiny_clip("0.2"), 1.0f)), nullptr);
  const RequestError full = refused(store.add("c", tiny_clip("0.3"), 1.0f));
  EXPECT_EQ(full.code, protocol::ErrorCode::ClipLimit);
  EXPECT_NE(full.message.find("maximum of 2 clips (--max-clips)"), std::string::npos)
      << full.message;
  EXPECT_NE(held(store.add("a again", tiny_clip("0.1"), 1.0f)), nullptr);
}

TEST(ClipStore, ByteLimitCountsTheBvhText) {
  const std::size_t size = tiny_clip("0.1").size();
  ClipStore store(8, 2 * size - 1);
  ASSERT_NE(held(store.add("a", tiny_clip("0.1"), 1.0f)), nullptr);
  const RequestError full = refused(store.add("b", tiny_clip("0.2"), 1.0f));
  EXPECT_EQ(full.code, protocol::ErrorCode::ClipLimit);
  EXPECT_NE(full.message.find("(--max-clip-bytes)"), std::string::npos) << full.message;
}

TEST(ClipStore, TextThatIsNotAUsableBvhIsRefusedWithoutTakingRoom) {
  ClipStore store(1, 1 << 20);
  const RequestError broken = refused(store.add("broken.bvh", "HIERARCHY\nROOT Hips\n{\n", 1.0f));
  EXPECT_EQ(broken.code, protocol::ErrorCode::ClipLoadFailed);
  EXPECT_NE(broken.message.find("broken.bvh"), std::string::npos) << broken.message;
  EXPECT_EQ(refused(store.add("still.bvh", tiny_clip("0.1", 0), 1.0f)).code,
            protocol::ErrorCode::ClipLoadFailed);
  EXPECT_EQ(refused(store.add("flat.bvh", tiny_clip(), 0.0f)).code,
            protocol::ErrorCode::InvalidArgument);
  EXPECT_NE(held(store.add("fine.bvh", tiny_clip(), 1.0f)), nullptr) << "nothing was counted";
}

TEST(ClipStore, ByteLimitCountsAGltfClipsFileBytes) {
  const std::filesystem::path data(SWEEPD_SHARED_DATA);
  if (!std::filesystem::exists(data / "models/makehuman_male_cmu.glb"))
    GTEST_SKIP() << "shared data absent (see ../shared/data/SOURCES.md)";
  const deform::Model male = io::load_gltf(data / "models/makehuman_male_cmu.glb");
  const std::filesystem::path file = std::filesystem::temp_directory_path() /
                                     ("clip_store_test_" + std::to_string(getpid()) + ".glb");
  io::testing::write_baked_gltf(male, io::testing::bake_cmu_clip(male, 6), file);
  const std::vector<std::uint8_t> gltf = io::read_file_bytes(file);
  std::filesystem::remove(file);

  ClipStore tight(8, gltf.size() - 1);
  const RequestError full = refused(tight.add_gltf("baked.glb", gltf, "linear", false));
  EXPECT_EQ(full.code, protocol::ErrorCode::ClipLimit);
  EXPECT_NE(full.message.find("a clip of " + std::to_string(gltf.size()) + " uploaded bytes"),
            std::string::npos)
      << full.message;

  ClipStore store(8, gltf.size() + tiny_clip().size());
  const ClipHandle linear = held(store.add_gltf("baked.glb", gltf, "linear", false));
  ASSERT_NE(linear, nullptr);
  EXPECT_EQ(linear->upload_bytes(), gltf.size());
  EXPECT_EQ(held(store.add_gltf("again.glb", gltf, "linear", false)), linear)
      << "the same bytes and animation are the held clip, counted once";
  EXPECT_NE(held(store.add("walk.bvh", tiny_clip(), 1.0f)), nullptr) << "what is left fits";
  // Played on two models, the clip is not copied: --max-clip-bytes bounds what players hold.
  auto model = std::make_shared<RegisteredModel>();
  model->bound.model = male;
  const ModelHandle first = model, second = std::make_shared<RegisteredModel>(*model);
  EXPECT_EQ(&linear->player(first)->motion(), &linear->clip());
  EXPECT_EQ(&linear->player(second)->motion(), &linear->clip());
  EXPECT_EQ(linear->player(first)->pose_at_frame(3).local_rotations,
            linear->player(second)->pose_at_frame(3).local_rotations);
  EXPECT_EQ(refused(store.add_gltf("baked.glb", gltf, "cubic", false)).code,
            protocol::ErrorCode::ClipLimit)
      << "another animation is another clip of the file's bytes";
}

TEST(ClipStore, ARangeOfMotionIsNamedByItsModelAndCountsItsKeys) {
  RegisteredModel model;
  model.content_id = std::string(64, 'a');
  model.name = "mannequin";
  model.bound.model = mannequin::make_mannequin({.target_vertices = 2000});
  model.bound.rig = deform::detect_rig_map(model.bound.model.skeleton);
  const motion::Clip expected =
      motion::range_of_motion(model.bound.model.skeleton, model.bound.rig).clip;
  std::size_t key_bytes = 0;
  for (const motion::KeyframeTrack& track : expected.tracks)
    key_bytes += (track.times.size() + track.values.size()) * sizeof(float);

  ClipStore tight(8, key_bytes - 1);
  EXPECT_EQ(refused(tight.add_range_of_motion(model)).code, protocol::ErrorCode::ClipLimit);

  ClipStore store(8, key_bytes);
  const ClipHandle rom = held(store.add_range_of_motion(model));
  ASSERT_NE(rom, nullptr);
  EXPECT_EQ(rom->name(), "range of motion");
  EXPECT_EQ(rom->clip().frame_count, expected.frame_count);
  EXPECT_EQ(rom->upload_bytes(), key_bytes);
  EXPECT_EQ(held(store.add_range_of_motion(model)), rom) << "held, counted once";
  RegisteredModel other = model;
  other.content_id = std::string(64, 'b');
  EXPECT_EQ(refused(store.add_range_of_motion(other)).code, protocol::ErrorCode::ClipLimit)
      << "another model's is another clip";
}

}  // namespace
}  // namespace sweepd::server
