// sweepctl pose -o FILE.pc2|FILE.mdd as a user runs it: the caches hold the very frames
// `sweepctl pose --frames` writes as .glb files, in glTF's or Blender's axes, and bad requests
// are refused naming the problem.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "io/gltf/gltf_load.h"
#include "tests/cli/sweepctl_process.h"
#include "tests/io/point_cache_read.h"

namespace {

namespace fs = std::filesystem;

using sweepd::test::run_sweepctl;
using sweepd::test::shared;
using sweepd::test::SweepctlResult;

struct SharedMale {
  fs::path model = shared("models/makehuman_male_cmu.glb");
  fs::path clip = shared("motion/cmu_01_01.bvh");
  bool present() const { return fs::exists(model) && fs::exists(clip); }
  std::string posing() const { return "pose " + model.string() + " --bvh " + clip.string(); }
};

// The largest distance between a cache's frame and the positions of a .glb frame, after `turn`.
template <typename Turn>
float largest_gap(const sweepd::test::PointCache& cache, int frame,
                  const std::vector<glm::vec3>& positions, Turn turn) {
  float gap = 0.0f;
  for (std::size_t v = 0; v < positions.size(); ++v)
    gap = std::max(gap,
                   glm::length(cache.positions[frame * positions.size() + v] - turn(positions[v])));
  return gap;
}

// Frames 10-12 of cmu_01_01 (120 fps) on the shared male as .glb frames, a PC2 cache in glTF's
// axes and an MDD cache in Blender's: the same float32 numbers, so within 1e-6 m (what a float32
// rounding of a coordinate under 2 m can differ by, were the paths to round differently).
TEST(SweepctlPointCache, CachesHoldThePoseFramesOfTheSharedMale) {
  const SharedMale male;
  if (!male.present()) GTEST_SKIP() << "shared data absent: " << male.model << ", " << male.clip;
  sweepd::test::ScratchDirectory dir("sweepctl_point_cache");
  const std::string frames = " --frames 10-12 -o ";
  SweepctlResult r = run_sweepctl(male.posing() + frames + (dir.path() / "frames").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_sweepctl(male.posing() + frames + (dir.path() / "m.pc2").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("wrote 3 frames of 14517 vertices"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("caching cmu_01_01.bvh: 100%"), std::string::npos)
      << "progress on stderr\n"
      << r.output;
  r = run_sweepctl(male.posing() + frames + (dir.path() / "m.mdd").string() + " --axes blender");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(fs::exists(dir.path() / "m.pc2.partial")) << "the partial file was renamed";

  const sweepd::test::PointCache pc2 = sweepd::test::read_point_cache(dir.path() / "m.pc2");
  const sweepd::test::PointCache mdd = sweepd::test::read_point_cache(dir.path() / "m.mdd");
  ASSERT_EQ(pc2.frames, 3);
  ASSERT_EQ(pc2.points, 14517);
  EXPECT_EQ(pc2.start, 10.0f) << "the clip frame of the first sample";
  EXPECT_EQ(pc2.sampling, 1.0f);
  ASSERT_EQ(mdd.frames, 3);
  ASSERT_EQ(mdd.points, 14517);
  // The clip's Frame Time is .0083333 s: frame 10 is at 0.083333 s (float32: 1e-7 s).
  EXPECT_NEAR(mdd.times[0], 10 * 0.0083333, 1e-6);
  EXPECT_NEAR(mdd.times[2], 12 * 0.0083333, 1e-6);
  for (int f = 0; f < 3; ++f) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05d.glb", 10 + f);
    const sweepd::deform::Model posed = sweepd::io::load_gltf(dir.path() / "frames" / name);
    ASSERT_EQ(posed.positions.size(), 14517u);
    EXPECT_LE(largest_gap(pc2, f, posed.positions, [](glm::vec3 p) { return p; }), 1e-6f)
        << "PC2 frame " << f;
    EXPECT_LE(
        largest_gap(mdd, f, posed.positions, [](glm::vec3 p) { return glm::vec3(p.x, -p.z, p.y); }),
        1e-6f)
        << "MDD frame " << f << " in Blender's axes";
  }
}

TEST(SweepctlPointCache, RefusesWhatCannotBeCachedNamingTheProblem) {
  const SharedMale male;
  if (!male.present()) GTEST_SKIP() << "shared data absent: " << male.model << ", " << male.clip;
  sweepd::test::ScratchDirectory dir("sweepctl_point_cache_refusals");
  const std::string out = (dir.path() / "m.pc2").string();
  struct Refusal {
    std::string arguments;
    int exit_code;
    std::string reason;
  };
  const std::vector<Refusal> refusals = {
      {male.posing() + " --frames 10-12 -o " + (dir.path() / "m.pc3").string(), 2,
       "not a '.pc3' file"},
      {male.posing() + " --frames 12-10 -o " + out, 2,
       "'12-10' is an empty range: its first frame comes after its last"},
      {male.posing() + " --frames 2750-2760 -o " + out, 1,
       "cmu_01_01.bvh: the clip has frames 0-2751; frame 2760 does not exist"},
      {male.posing() + " --time 1 -o " + out, 2, "not a time (--time)"},
      {"pose " + male.model.string() + " -o " + out, 2, "a point cache holds clip frames"},
      {male.posing() + " --frame 3 -o " + (dir.path() / "m.glb").string() + " --axes blender", 2,
       "--axes applies to a point cache"},
      {male.posing() + " --frames 1-2 -o " + out + " --axes zup", 2, "--axes"},
  };
  for (const Refusal& refusal : refusals) {
    const SweepctlResult r = run_sweepctl(refusal.arguments);
    EXPECT_EQ(r.exit_code, refusal.exit_code) << refusal.arguments << "\n" << r.output;
    EXPECT_NE(r.output.find(refusal.reason), std::string::npos) << refusal.arguments << "\n"
                                                                << r.output;
  }
  EXPECT_TRUE(fs::is_empty(dir.path())) << "no cache, no partial file, no folder left";
}

}  // namespace
