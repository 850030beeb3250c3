// sweepctl pose --clip / --clip-from as a user runs them, on a glTF made in the test
// (tests/io/baked_gltf_clip.h: cmu_01_01 retargeted onto the shared male, baked as LINEAR, STEP
// and CUBICSPLINE animations of the male's own joints):
// - `--clip NAME|INDEX --frame N` at a key frame poses the model exactly as `--pose` with that
//   key's rotations and root translation does (the same vertices: the same pose, bit for bit);
//   so does `--time` at the key's time;
// - `--clip-from FILE` retargets the file's clip onto another model file;
// - a bad clip name or index, and frame flags without a clip, exit non-zero naming the problem;
// - `inspect` lists the file's animations with their duration, frames, channels and joints.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "io/gltf/gltf_load.h"
#include "io/json/pose_json.h"
#include "tests/cli/sweepctl_process.h"
#include "tests/io/baked_gltf_clip.h"

namespace {

namespace fs = std::filesystem;

using sweepd::test::run_sweepctl;
using sweepd::test::shared;
using sweepd::test::SweepctlResult;

constexpr int kKeys = 6;
constexpr int kKey = 3;

class SweepctlGltfClip : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(shared("models/makehuman_male_cmu.glb")) ||
        !fs::exists(shared("motion/cmu_01_01.bvh")))
      GTEST_SKIP() << "shared data absent (see ../shared/data/SOURCES.md)";
    dir_ = sweepd::test::process_scratch("sweepctl_gltf_clip");
    model_ = sweepd::io::load_gltf(shared("models/makehuman_male_cmu.glb"));
    baked_ = sweepd::io::testing::bake_cmu_clip(model_, kKeys);
    sweepd::io::testing::write_baked_gltf(model_, baked_, dir_ / "baked.glb");
    sweepd::deform::Pose key;
    key.local_rotations = baked_.rotations[kKey];
    key.root_translation = baked_.root[kKey];
    sweepd::io::save_pose_json(key, model_.skeleton, dir_ / "key.json");
  }

  SweepctlResult pose(const std::string& flags, const std::string& out) const {
    return run_sweepctl("pose " + (dir_ / "baked.glb").string() + " " + flags + " -o " +
                        (dir_ / out).string());
  }
  std::vector<glm::vec3> positions(const std::string& out) const {
    return sweepd::io::load_gltf(dir_ / out).positions;
  }

  fs::path dir_;
  sweepd::deform::Model model_;
  sweepd::io::testing::BakedClip baked_;
};

TEST_F(SweepctlGltfClip, AKeyFramePosesAsItsBakedRotationsDo) {
  const SweepctlResult reference = pose("--pose " + (dir_ / "key.json").string(), "key.glb");
  ASSERT_EQ(reference.exit_code, 0) << reference.output;
  const std::vector<glm::vec3> expected = positions("key.glb");
  for (const std::string& flags :
       {std::string("--clip linear --frame 3"), std::string("--clip 1 --frame 3"),
        std::string("--clip cubic --frames 3-3"),
        "--clip linear --time " + std::to_string(double{baked_.times[kKey]})}) {
    const bool range = flags.find("--frames") != std::string::npos;
    const SweepctlResult r = pose(flags, range ? "frames" : "clip.glb");
    ASSERT_EQ(r.exit_code, 0) << flags << "\n" << r.output;
    EXPECT_EQ(positions(range ? "frames/frame_00003.glb" : "clip.glb"), expected) << flags;
  }
}

TEST_F(SweepctlGltfClip, ClipFromRetargetsAnotherFilesClip) {
  const SweepctlResult r =
      run_sweepctl("pose " + shared("models/makehuman_male_cmu.glb").string() + " --clip-from " +
                   (dir_ / "baked.glb").string() + " --clip cubic --frame 2 -o " +
                   (dir_ / "retargeted.glb").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(positions("retargeted.glb").size(), model_.positions.size());
}

TEST_F(SweepctlGltfClip, BadClipsAndFlagsWithoutAClipAreRefusedNamingTheProblem) {
  const SweepctlResult name = pose("--clip walk", "x.glb");
  EXPECT_NE(name.exit_code, 0);
  EXPECT_NE(name.output.find("no animation named 'walk' (the file's animations: 0 'linear', 1 "
                             "'step', 2 'cubic')"),
            std::string::npos)
      << name.output;
  const SweepctlResult index = pose("--clip 5", "x.glb");
  EXPECT_NE(index.exit_code, 0);
  EXPECT_NE(index.output.find("no animation 5: the file has 3"), std::string::npos) << index.output;
  const SweepctlResult past = pose("--clip linear --frame 6", "x.glb");
  EXPECT_NE(past.exit_code, 0);
  EXPECT_NE(past.output.find("frame 6 does not exist"), std::string::npos) << past.output;
  const SweepctlResult no_clip = pose("--frame 2", "x.glb");
  EXPECT_NE(no_clip.exit_code, 0);
  EXPECT_NE(no_clip.output.find("give --bvh, --clip or --clip-from"), std::string::npos)
      << no_clip.output;
}

TEST_F(SweepctlGltfClip, InspectListsTheFilesAnimations) {
  const SweepctlResult r = run_sweepctl("inspect " + (dir_ / "baked.glb").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // Every joint's rotation and the root's translation, 6 keys 1/30 s apart.
  const std::size_t joints = model_.skeleton.joints.size();
  const std::string played = std::to_string(joints + 1) + " channels played, drives " +
                             std::to_string(joints) + " of " + std::to_string(joints) + " joints";
  EXPECT_NE(r.output.find("animations:  3 (pose --clip NAME|INDEX)"), std::string::npos)
      << r.output;
  for (const std::string& line :
       {"0 'linear': 0.167 s, 6 frames at 30.00 fps, " + played + " (LINEAR)",
        "1 'step': 0.167 s, 6 frames at 30.00 fps, " + played + " (STEP)",
        "2 'cubic': 0.167 s, 6 frames at 30.00 fps, " + played + " (CUBICSPLINE)"})
    EXPECT_NE(r.output.find(line), std::string::npos) << line << "\n" << r.output;
}

// With --model, each animation is also retargeted onto that model (as `pose --clip-from` plays
// it) and what that leaves unmapped is named under it (issue 48 item 4): here the male's own
// clip onto the male, whose fingers the clip's hands leave still (motion/retarget.h).
TEST_F(SweepctlGltfClip, InspectWithAModelNamesWhatEachAnimationLeavesUnmapped) {
  const SweepctlResult r = run_sweepctl("inspect " + (dir_ / "baked.glb").string() + " --model " +
                                        shared("models/makehuman_male_cmu.glb").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::size_t joints = model_.skeleton.joints.size();
  std::size_t at = r.output.find("2 'cubic': ");
  ASSERT_NE(at, std::string::npos) << r.output;
  at = r.output.find("    retargeted onto ", at);
  ASSERT_NE(at, std::string::npos) << r.output;
  EXPECT_NE(r.output.find(" of " + std::to_string(joints) + " clip joints matched", at),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("    - model joints the clip leaves without motion, at their rest "
                          "rotation (8): ",
                          at),
            std::string::npos)
      << r.output;
}

}  // namespace
