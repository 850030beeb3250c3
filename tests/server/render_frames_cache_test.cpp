// client_examples/render_frames --format pc2|mdd against the real daemon on loopback: the cache
// of a range holds `sweepctl pose`'s frames of the same model and clip; shards' caches joined by
// `sweepctl join-cache` are the single-shard cache byte for byte; a complete cache is skipped on
// a rerun; flags of the other output are usage errors naming the flag.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "tests/io/point_cache_read.h"
#include "tests/server/client_run.h"
#include "tests/server/daemon_process.h"
#include "tests/server/sweepctl_remote.h"

namespace sweepd::test::render_frames_cache_test {
namespace {

constexpr int kFirst = 300, kLast = 305;  // a stretch of the clip where the body moves

ClientRun run_render_frames(const std::string& arguments) {
  return run_client(std::string(SWEEPD_RENDER_FRAMES) + " " + arguments);
}

// The largest coordinate difference between two caches' frames (infinity when their sizes
// differ).
float largest_difference(const PointCache& a, const PointCache& b) {
  if (a.positions.size() != b.positions.size() || a.positions.empty()) return INFINITY;
  float largest = 0.0f;
  for (std::size_t i = 0; i < a.positions.size(); ++i) {
    const glm::vec3 d = glm::abs(a.positions[i] - b.positions[i]);
    largest = std::max({largest, d.x, d.y, d.z});
  }
  return largest;
}

class RenderFramesCache : public ClipClientTest {
 protected:
  RenderFramesCache() : ClipClientTest("render_frames_cache") {}
  // The shared male uploaded, the clip at scale 1 as `sweepctl pose --bvh` reads it.
  std::string arguments(const std::string& rest) const {
    return "--server 127.0.0.1:" + std::to_string(daemon_->port()) + " --token t0k --model-file " +
           kSharedMale.string() + " --bvh " + clip_.string() + " --bvh-scale 1 --frames " +
           std::to_string(kFirst) + "-" + std::to_string(kLast) + " " + rest;
  }
  fs::path sweepctl_cache(const std::string& name, const std::string& axes) const {
    const fs::path file = directory_ / name;
    const ClientRun r = run_sweepctl("pose " + kSharedMale.string() + " --bvh " + clip_.string() +
                                     " --frames " + std::to_string(kFirst) + "-" +
                                     std::to_string(kLast) + " -o " + file.string() + axes);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return file;
  }
};

TEST_F(RenderFramesCache, ShardCachesHoldSweepctlPoseFramesAndJoinToTheWholeRange) {
  if (!fs::exists(kSharedMale)) GTEST_SKIP() << "shared data absent: " << kSharedMale;
  const fs::path whole = directory_ / "whole", shards = directory_ / "shards";
  ClientRun r = run_render_frames(arguments("--format pc2 -o " + whole.string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(render_counts(r.output), (std::array<int, 5>{6, 0, 6, 0, 0})) << r.output;
  const fs::path whole_pc2 = whole / "cmu_01_01.00300-00305.pc2";
  EXPECT_NE(r.output.find("wrote " + whole_pc2.string() +
                          ": frames 300-305 of 14517 vertices "
                          "(PC2, glTF's Y-up axes)"),
            std::string::npos)
      << r.output;

  // The server deforms as sweepctl does here (the same library, clip and model): 1e-5 m leaves
  // room for float arithmetic in another order, far below a frame-to-frame move (centimetres).
  const PointCache served = read_point_cache(whole_pc2);
  const PointCache local = read_point_cache(sweepctl_cache("local.pc2", ""));
  EXPECT_EQ(served.frames, 6);
  EXPECT_EQ(served.start, 300.0f) << "the first frame's number";
  EXPECT_LT(largest_difference(served, local), 1e-5f);

  // Three shards, joined in the wrong order on the command line.
  for (int shard = 0; shard < 3; ++shard) {
    r = run_render_frames(
        arguments("--format pc2 --shard " + std::to_string(shard) + "/3 -o " + shards.string()));
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  const fs::path joined = directory_ / "joined.pc2";
  r = run_sweepctl("join-cache " + (shards / "cmu_01_01.00304-00305.pc2").string() + " " +
                   (shards / "cmu_01_01.00300-00301.pc2").string() + " " +
                   (shards / "cmu_01_01.00302-00303.pc2").string() + " -o " + joined.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("3 caches joined, frames 300-305 of 14517 vertices"), std::string::npos)
      << r.output;
  EXPECT_EQ(file_bytes(joined), file_bytes(whole_pc2)) << "the shards joined are the whole";
  // Two shards with the middle one missing: a gap, named.
  r = run_sweepctl("join-cache " + (shards / "cmu_01_01.00300-00301.pc2").string() + " " +
                   (shards / "cmu_01_01.00304-00305.pc2").string() + " -o " +
                   (directory_ / "gap.pc2").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("non-contiguous caches"), std::string::npos) << r.output;

  // Blender's axes in an MDD: sweepctl's --axes blender cache, within the same 1e-5 m.
  r = run_render_frames(arguments("--format mdd --axes blender -o " + whole.string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_LT(largest_difference(read_point_cache(whole / "cmu_01_01.00300-00305.mdd"),
                               read_point_cache(sweepctl_cache("local.mdd", " --axes blender"))),
            1e-5f);

  // A complete cache is not rendered again.
  r = run_render_frames(arguments("--format pc2 -o " + whole.string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(render_counts(r.output), (std::array<int, 5>{0, 6, 6, 0, 0})) << r.output;
}

TEST_F(RenderFramesCache, FlagsOfTheOtherOutputAreUsageErrors) {
  const std::string out = " -o " + (directory_ / "x").string();
  ClientRun r = run_render_frames(arguments("--axes blender" + out));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--axes applies to a point cache"), std::string::npos) << r.output;
  r = run_render_frames(arguments("--format pc2 --normals" + out));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--normals applies to EXR position maps"), std::string::npos) << r.output;
  r = run_render_frames(arguments("--format obj" + out));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--format"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace sweepd::test::render_frames_cache_test
