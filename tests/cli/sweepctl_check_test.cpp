// sweepctl check and sweepctl rom as a user runs them, on the shared male (issue 47 items 1-2):
// - `check MODEL --json` measures every body region with sweep, LBS and DQS over the range of
//   motion, and its exit status says whether some sweep region was worse than the better
//   baseline (1) or not (0), as the JSON's own verdict does;
// - the sweep's known advantage shows: at the crotch (torso region, hip flexion 130°) LBS
//   stretches an edge 9.1x its rest length, the sweep 3.4x — asserted as sweep < 0.6 x LBS,
//   a margin that a regression of the torso's sweep would cross;
// - `rom MODEL -o rom.glb` writes the range of motion with the model; `check rom.glb --clip
//   "range of motion"` measures the same figures as `check MODEL` (the model and the clip both
//   went through a glTF file: float32 positions and rotations, so within 1e-3 relative);
// - `--sections` adds the smallest limb section and crossing pairs per method;
// - `--sheet` writes a PNG; bad flags are usage errors naming the flag.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <stdexcept>
#include <string>

#include "tests/cli/sweepctl_process.h"

namespace {

namespace fs = std::filesystem;

using sweepd::test::run_sweepctl;
using sweepd::test::shared;
using sweepd::test::SweepctlResult;

class SweepctlCheck : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(shared("models/makehuman_male_cmu.glb")))
      GTEST_SKIP() << "shared data absent (see ../shared/data/SOURCES.md)";
    dir_ = sweepd::test::process_scratch("sweepctl_check");
  }
  static std::string male() { return shared("models/makehuman_male_cmu.glb").string(); }

  fs::path dir_;
};

// The method entry of a region in check's JSON.
const nlohmann::json& figures(const nlohmann::json& report, const std::string& region,
                              const std::string& method) {
  for (const nlohmann::json& r : report["regions"])
    if (r["region"] == region)
      for (const nlohmann::json& m : r["methods"])
        if (m["method"] == method) return m;
  throw std::runtime_error("no " + region + " / " + method + " in the report");
}

TEST_F(SweepctlCheck, JudgesEveryRegionAgainstTheBetterBaselineAndExitsByTheVerdict) {
  const SweepctlResult result = run_sweepctl("check " + male() + " --json", "2>/dev/null");
  const nlohmann::json report = nlohmann::json::parse(result.output);
  EXPECT_EQ(result.exit_code, report["worse_than_skinning"].get<bool>() ? 1 : 0);
  EXPECT_EQ(report["frames"], 289) << "every 5th of the 1,441 frames of 48 moves";
  std::set<std::string> regions;
  bool any_worse = false;
  for (const nlohmann::json& r : report["regions"]) {
    regions.insert(r["region"].get<std::string>());
    for (const nlohmann::json& m : r["methods"]) {
      EXPECT_GE(m["stretch"].get<double>(), 1.0);
      EXPECT_LE(m["squash"].get<double>(), 1.0);
      if (m["method"] == "sweep") any_worse = any_worse || m["worse_frames"].get<int>() > 0;
    }
  }
  EXPECT_EQ(any_worse, report["worse_than_skinning"].get<bool>());
  for (const char* region : {"torso", "neck", "head", "left arm", "right arm", "left hand",
                             "right hand", "left leg", "right leg", "left foot", "right foot"})
    EXPECT_TRUE(regions.count(region)) << region;
  const double sweep = figures(report, "torso", "sweep")["stretch"];
  const double lbs = figures(report, "torso", "lbs")["stretch"];
  EXPECT_LT(sweep, 0.6 * lbs) << "the crotch: the sweep's advantage over LBS";
}

TEST_F(SweepctlCheck, TheRangeOfMotionWrittenAsGltfMeasuresAsTheBuiltInOne) {
  const fs::path rom = dir_ / "rom.glb";
  const SweepctlResult wrote = run_sweepctl("rom " + male() + " -o " + rom.string());
  ASSERT_EQ(wrote.exit_code, 0) << wrote.output;
  EXPECT_NE(wrote.output.find("48 moves, 1441 frames at 30 fps"), std::string::npos)
      << wrote.output;
  const nlohmann::json built_in =
      nlohmann::json::parse(run_sweepctl("check " + male() + " --json", "2>/dev/null").output);
  const nlohmann::json from_file = nlohmann::json::parse(
      run_sweepctl("check " + rom.string() + " --clip 'range of motion' --step 5 --json", "2>/dev/null")
          .output);
  ASSERT_EQ(from_file["frames"], built_in["frames"]);
  for (const char* region : {"torso", "left arm", "right leg", "neck"})
    for (const char* method : {"sweep", "lbs", "dqs"}) {
      const double a = figures(built_in, region, method)["stretch"];
      const double b = figures(from_file, region, method)["stretch"];
      EXPECT_NEAR(b, a, 1e-3 * a) << region << " " << method;
    }
}

// --sections adds the whole body's smallest limb section ratio and crossing triangle pairs per
// method (metrics::QualityMeter's, at every third measured frame).
TEST_F(SweepctlCheck, SectionsAddTheSmallestLimbSectionAndCrossingPairs) {
  const nlohmann::json report = nlohmann::json::parse(
      run_sweepctl("check " + male() + " --step 15 --sections --json", "2>/dev/null").output);
  for (const char* method : {"sweep", "lbs", "dqs"}) {
    const nlohmann::json& m = figures(report, "torso", method);
    ASSERT_TRUE(m.contains("smallest_section")) << method;
    EXPECT_GT(m["smallest_section"].get<double>(), 0.0) << method;
    EXPECT_LE(m["smallest_section"].get<double>(), 1.0) << method;
    EXPECT_GE(m["crossing_pairs"].get<int>(), 0) << method;
  }
  const std::string table = run_sweepctl("check " + male() + " --step 60 --sections", "2>/dev/null").output;
  EXPECT_NE(table.find("lbs            smallest limb section"), std::string::npos) << table;
}

TEST_F(SweepctlCheck, SheetIsAPngAndBadFlagsAreUsageErrors) {
  const fs::path png = dir_ / "worst.png";
  const SweepctlResult result =
      run_sweepctl("check " + male() + " --step 60 --sheet " + png.string(), "2>&1");
  ASSERT_TRUE(fs::exists(png)) << result.output;
  std::ifstream file(png, std::ios::binary);
  char signature[4] = {};
  file.read(signature, 4);
  EXPECT_EQ(std::string(signature + 1, 3), "PNG");
  EXPECT_NE(result.output.find("wrote " + png.string()), std::string::npos) << result.output;

  const SweepctlResult zero = run_sweepctl("check " + male() + " --step 0");
  EXPECT_EQ(zero.exit_code, 2);
  EXPECT_NE(zero.output.find("--step"), std::string::npos) << zero.output;
  const SweepctlResult unknown = run_sweepctl("check " + male() + " --method sweep,lbz");
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.output.find("--method"), std::string::npos) << unknown.output;
}

}  // namespace
