// Blender plays sweepd's point caches: Debian's Blender 3.4, headless, imports the shared male
// with its own glTF importer, puts a Mesh Cache modifier on the body reading the PC2 and MDD
// files `sweepctl pose` wrote, and its evaluated vertices are sweepctl's frames
// (tests/cli/blender_point_cache.py does the Blender side). Skips where blender is absent.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "io/gltf/gltf_load.h"
#include "tests/cli/sweepctl_process.h"
#include "tests/deploy/shell_command.h"

namespace {

namespace fs = std::filesystem;

using sweepd::test::run_command;
using sweepd::test::run_sweepctl;
using sweepd::test::shared;

void write_floats(const fs::path& file, const std::vector<glm::vec3>& positions,
                  std::ios::openmode mode = std::ios::trunc) {
  std::ofstream out(file, std::ios::binary | mode);
  out.write(reinterpret_cast<const char*>(positions.data()),
            static_cast<std::streamsize>(positions.size() * sizeof(glm::vec3)));
}

// Frames 10-12 of cmu_01_01 on the shared male: a Z-up PC2 and MDD played with the modifier's
// default axes, and a Y-up (glTF) PC2 played with the axes docs/sweepctl.md gives. Vertex i is
// compared with sweepd's vertex i: the script first shows that the imported rest mesh is
// sweepd's rest mesh vertex for vertex (the importer neither reorders nor splits this model's
// vertices), so an index-wise match is the strict test (a set or nearest-vertex match would
// pass a cache that scrambles the mesh). 1e-5 m: float32 positions of a 1.75 m body round to
// 1e-7 m; the rest mesh passes through the importer's float arithmetic, the frames do not.
TEST(BlenderPointCache, MeshCacheModifierPlaysThePoseFramesOnTheImportedMale) {
  const fs::path male = shared("models/makehuman_male_cmu.glb");
  const fs::path clip = shared("motion/cmu_01_01.bvh");
  if (!fs::exists(male) || !fs::exists(clip))
    GTEST_SKIP() << "shared data absent: " << male << ", " << clip;
  if (run_command("command -v blender").exit_code != 0)
    GTEST_SKIP() << "blender is not installed (Debian's package `blender`: "
                    "deploy/install-deps.sh installs it)";
  sweepd::test::ScratchDirectory dir("blender_point_cache");
  const std::string posing = "pose " + male.string() + " --bvh " + clip.string() +
                             " --frames 10-12 -o " + dir.path().string() + "/";
  for (const std::string out :
       {"frames", "z.pc2 --axes blender", "z.mdd --axes blender", "y.pc2"}) {
    const sweepd::test::SweepctlResult r = run_sweepctl(posing + out);
    ASSERT_EQ(r.exit_code, 0) << out << "\n" << r.output;
  }
  write_floats(dir.path() / "rest.f32", sweepd::io::load_gltf(male).positions);
  for (const char* frame : {"frame_00010.glb", "frame_00011.glb", "frame_00012.glb"})
    write_floats(dir.path() / "frames.f32",
                 sweepd::io::load_gltf(dir.path() / "frames" / frame).positions, std::ios::app);

  const fs::path d = dir.path();
  const sweepd::test::CommandResult blender =
      run_command("blender -b --factory-startup --python-exit-code 1 --python " +
                  (fs::path(SWEEPD_SOURCE_DIR) / "tests/cli/blender_point_cache.py").string() +
                  " -- " + male.string() + " " + (d / "rest.f32").string() + " " +
                  (d / "frames.f32").string() + " 3 " + (d / "z.pc2").string() + ":blender " +
                  (d / "z.mdd").string() + ":blender " + (d / "y.pc2").string() + ":gltf");
  ASSERT_EQ(blender.exit_code, 0) << blender.output;
  std::istringstream lines(blender.output);
  int gaps = 0;
  for (std::string line; std::getline(lines, line);) {
    const std::size_t at = line.rfind(" gap ");
    if (at == std::string::npos || line.find("Error") != std::string::npos) continue;
    ++gaps;
    EXPECT_LE(std::stod(line.substr(at + 5)), 1e-5) << line;
  }
  EXPECT_EQ(gaps, 1 + 3 * 3) << "the rest mesh and 3 frames of 3 caches\n" << blender.output;
}

}  // namespace
