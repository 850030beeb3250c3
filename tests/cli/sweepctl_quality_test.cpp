// sweepctl's quality commands as a user runs them: `metrics` (a posed elbow and a few clip
// frames, table, JSON and CSV, bad arguments), `edit` (edits stored in a .sweepbind that
// reads back, a bad edits file refused with its name), and `bind`'s self-check as `bind` and
// `inspect` print it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "io/sweepbind/sweepbind.h"
#include "tests/scratch_directory.h"

namespace sweepctl_quality_test {
namespace {

namespace fs = std::filesystem;

fs::path scratch() { return sweepd::test::process_scratch("sweepctl_quality"); }

std::string read_text(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Runs sweepctl with these arguments; returns its exit code and fills `output` with its stdout
// followed by its stderr (progress and errors).
int sweepctl(const std::string& arguments, std::string& output) {
  const fs::path out = scratch() / "stdout.txt", err = scratch() / "stderr.txt";
  const std::string command =
      std::string(SWEEPD_SWEEPCTL) + " " + arguments + " > " + out.string() + " 2> " + err.string();
  const int status = std::system(command.c_str());
  output = read_text(out) + read_text(err);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

const fs::path kMale = fs::path(SWEEPD_SHARED_DATA) / "models/makehuman_male_cmu.glb";
const fs::path kClip = fs::path(SWEEPD_SHARED_DATA) / "motion/cmu_01_01.bvh";

// `sweepctl metrics ARGUMENTS --json`'s report; null (and a failure) when it exits non-zero.
nlohmann::json metrics_report(const std::string& arguments) {
  std::string out;
  const int status = sweepctl("metrics " + arguments + " --json", out);
  EXPECT_EQ(status, 0) << out;
  if (status != 0) return nullptr;
  return nlohmann::json::parse(out.substr(0, out.rfind('}') + 1));
}

#define REQUIRE_DATA() \
  if (!fs::exists(kMale) || !fs::exists(kClip)) GTEST_SKIP() << "shared data absent"

TEST(SweepctlMetrics, ElbowPoseAsJsonShowsVolumePreservationAtWork) {
  REQUIRE_DATA();
  const fs::path pose = scratch() / "elbow.json";
  std::ofstream(pose)
      << R"({"rotations": {"LeftForeArm": {"axis": [-0.7, -0.7, 0], "degrees": 70}}})";
  const nlohmann::json report = metrics_report(kMale.string() + " --pose " + pose.string() +
                                               " --method sweep,sweep+volume,lbs");
  ASSERT_FALSE(report.is_null());
  ASSERT_EQ(report["methods"].size(), 3u);
  auto metric = [&](int method, const std::string& name) {
    for (const auto& m : report["methods"][method]["metrics"])
      if (m["name"] == name) return m["worst"].get<double>();
    ADD_FAILURE() << "no metric " << name;
    return 0.0;
  };
  // The left elbow turned 70° further (about cross(upper arm, +Z); a 116° flexion): the plain
  // sweep loses volume (-3.02 % measured; its mitred elbow key keeps the outside of the bend,
  // LBS loses -5.85 %), preservation holds the sweep integral and with it the closed region
  // within issue 5's 2 % (+0.42 % measured: the elbow's ellipse sits on its section,
  // KeyEllipse::offset; a gain), and LBS has no sweep integral.
  EXPECT_LT(metric(0, "left arm mesh volume %"), -2.0);
  EXPECT_LT(std::abs(metric(1, "left arm mesh volume %")), 2.0);
  for (const auto& m : report["methods"][2]["metrics"])
    EXPECT_EQ(m["name"].get<std::string>().find("sweep integral"), std::string::npos);
  EXPECT_LT(report["methods"][2]["rest_error_m"].get<double>(), 1e-5);  // LBS at rest: exact
  // A pose file has no frame: the report names the file and gives no frame of the worst
  // (issue 52 item 6: it said frame 0).
  EXPECT_EQ(report["pose"], pose.string());
  for (const auto& m : report["methods"][0]["metrics"])
    EXPECT_TRUE(m["worst_frame"].is_null()) << m;
}

TEST(SweepctlMetrics, ATimeInTheClipIsReportedAsItsTimeNotAsFrameZero) {
  REQUIRE_DATA();
  const nlohmann::json report =
      metrics_report(kMale.string() + " --bvh " + kClip.string() + " --time 5 --method lbs");
  ASSERT_FALSE(report.is_null());
  EXPECT_EQ(report["time_seconds"], 5.0);
  EXPECT_EQ(report["frames"], 1);
  ASSERT_FALSE(report["methods"][0]["metrics"].empty());
  for (const auto& m : report["methods"][0]["metrics"])
    EXPECT_TRUE(m["worst_frame"].is_null()) << m;
}

TEST(SweepctlMetrics, ClipFramesGiveWorstMeanAndFrameAsCsvAndTable) {
  REQUIRE_DATA();
  std::string csv, table;
  const std::string common = "metrics " + kMale.string() + " --bvh " + kClip.string() +
                             " --frames 0-20 --step 10 --method dqs";
  ASSERT_EQ(sweepctl(common + " --csv", csv), 0) << csv;
  EXPECT_EQ(csv.rfind("method,metric,worst,mean,worst_frame\n", 0), 0u) << csv;
  std::istringstream lines(csv);
  std::string line;
  int rows = 0, twists = 0;
  while (std::getline(lines, line)) {
    if (!line.starts_with("dqs,") || line.starts_with("dqs,rest")) continue;
    const int frame = std::stoi(line.substr(line.rfind(',') + 1));
    if (line.starts_with("dqs,candy wrapper")) {  // a twist pose, not a clip frame
      EXPECT_EQ(frame, -1) << line;
      ++twists;
      continue;
    }
    EXPECT_TRUE(frame == 0 || frame == 10 || frame == 20) << line;  // a measured frame
    ++rows;
  }
  // Six part volumes, section ratio, crossings, whole-body contact pairs, the longest and the
  // shortest edge, and per part the crease anywhere and at keys (no kink: DQS has no sweep); the
  // candy wrapper at 90 and 180 degrees.
  EXPECT_EQ(rows, 6 + 5 + 2 * 6);
  EXPECT_EQ(twists, 2);
  ASSERT_EQ(sweepctl(common, table), 0) << table;
  EXPECT_NE(table.find("at frame"), std::string::npos) << table;
}

// The lines of `text` that start with `prefix` (after leading spaces), in order.
std::vector<std::string> lines_starting(const std::string& text, const std::string& prefix) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    const std::size_t start = line.find_first_not_of(' ');
    if (start != std::string::npos && line.compare(start, prefix.size(), prefix) == 0)
      lines.push_back(line.substr(start));
  }
  return lines;
}

// The (pose, region) pairs a self-check line counts first: "... worse in N (pose, region) pairs".
int worse_pairs(const std::string& line) {
  const std::size_t at = line.find("worse in ");
  return at == std::string::npos ? -1 : std::atoi(line.c_str() + at + 9);
}

TEST(SweepctlBind, ChecksItselfAndInspectSaysTheSameOfTheStoredBinding) {
  REQUIRE_DATA();
  const fs::path plain = scratch() / "checked.sweepbind", adapted = scratch() / "adapted.sweepbind";
  std::string bind, bind_adapted, inspect, inspect_adapted;
  ASSERT_EQ(sweepctl("bind " + kMale.string() + " -o " + plain.string() + " --no-adapt", bind), 0)
      << bind;
  ASSERT_EQ(sweepctl("bind " + kMale.string() + " -o " + adapted.string(), bind_adapted), 0)
      << bind_adapted;
  ASSERT_EQ(sweepctl("inspect " + plain.string(), inspect), 0) << inspect;
  ASSERT_EQ(sweepctl("inspect " + adapted.string(), inspect_adapted), 0) << inspect_adapted;
  // The male loses to skinning on his range of motion (docs/quality/): the self-check says so,
  // with a warning per region that names both length ratios.
  const auto checked = lines_starting(bind, "self-check (48 range-of-motion peaks");
  ASSERT_EQ(checked.size(), 1u) << bind;
  EXPECT_GT(worse_pairs(checked[0]), 0) << checked[0];
  const auto warnings = lines_starting(bind, "warning: ");
  ASSERT_FALSE(warnings.empty()) << bind;
  for (const std::string& w : warnings)
    EXPECT_NE(w.find("worse than skinning in "), std::string::npos) << w;
  EXPECT_TRUE(std::any_of(warnings.begin(), warnings.end(), [](const std::string& w) {
    return w.starts_with("warning: left arm:") &&
           w.find("the sweep stretches an edge") != std::string::npos;
  })) << bind;
  // inspect runs the same check on the stored binding: the same count, the same warnings.
  const auto inspected = lines_starting(inspect, "self-check (48 range-of-motion peaks");
  ASSERT_EQ(inspected.size(), 1u) << inspect;
  EXPECT_EQ(worse_pairs(inspected[0]), worse_pairs(checked[0]));
  EXPECT_EQ(lines_starting(inspect, "warning: "), warnings);
  EXPECT_TRUE(lines_starting(inspect, "adapted: ").empty()) << inspect;
  // By default bind adapts: never more pairs worse than as bound (on the male today it keeps
  // every sweep: each candidate nears a pair to losing), it says which sweeps it fitted again,
  // and the stored binding carries them: inspect counts what bind counted after.
  const auto adapted_line = lines_starting(bind_adapted, "self-check (48 range-of-motion peaks");
  ASSERT_EQ(adapted_line.size(), 1u) << bind_adapted;
  const std::size_t after_at = adapted_line[0].find(" as bound, ");
  ASSERT_NE(after_at, std::string::npos) << adapted_line[0];
  const int after = std::atoi(adapted_line[0].c_str() + after_at + 11);
  EXPECT_EQ(worse_pairs(adapted_line[0]), worse_pairs(checked[0]));
  EXPECT_LE(after, worse_pairs(checked[0])) << adapted_line[0];
  const auto notes = lines_starting(bind_adapted, "adapted: ");
  EXPECT_EQ(notes.empty(), after == worse_pairs(checked[0])) << bind_adapted;
  EXPECT_EQ(lines_starting(inspect_adapted, "adapted: "), notes);
  const auto inspected_adapted = lines_starting(inspect_adapted, "self-check (48");
  ASSERT_EQ(inspected_adapted.size(), 1u) << inspect_adapted;
  EXPECT_EQ(worse_pairs(inspected_adapted[0]), after);
  std::size_t chosen = 0;
  for (std::size_t at = 0;
       (at = inspect_adapted.find("chosen by the self-check", at)) != std::string::npos; ++at)
    ++chosen;
  EXPECT_EQ(chosen, notes.size()) << inspect_adapted;
}

TEST(SweepctlBind, StoresTheSmoothOrientationCurveWhoseSweepsHaveNoKink) {
  REQUIRE_DATA();
  const fs::path bound = scratch() / "smooth.sweepbind";
  std::string out;
  ASSERT_EQ(
      sweepctl("bind " + kMale.string() + " -o " + bound.string() + " --orientation smooth", out),
      0)
      << out;
  EXPECT_EQ(sweepd::io::load_sweepbind(bound).options.orientation_curve,
            sweepd::deform::OrientationCurveKind::kSmooth);
  // The same clip frame from the stored smooth binding and bound linear on the spot: the
  // linear sweeps kink at their keys (tens of degrees on a walking clip), the smooth ones only
  // by the metric's one-sided differences (below 1.5°; metrics/crease_metrics.h).
  auto largest_kink = [&](const std::string& model) {
    std::string json;
    EXPECT_EQ(sweepctl("metrics " + model + " --bvh " + kClip.string() +
                           " --frame 100 --method sweep --json",
                       json),
              0)
        << json;
    double worst = 0.0;
    const auto report = nlohmann::json::parse(json.substr(0, json.rfind('}') + 1));
    for (const auto& m : report["methods"][0]["metrics"])
      if (m["name"].get<std::string>().ends_with("kink deg"))
        worst = std::max(worst, m["worst"].get<double>());
    return worst;
  };
  EXPECT_LT(largest_kink(bound.string()), 1.5);
  EXPECT_GT(largest_kink(kMale.string()), 10.0);
  EXPECT_EQ(sweepctl("bind " + kMale.string() + " -o x.sweepbind --orientation wavy", out), 2);
  EXPECT_NE(out.find("--orientation"), std::string::npos) << out;
}

TEST(SweepctlMetrics, RefusesBadArgumentsWithUsage) {
  std::string out;
  EXPECT_EQ(sweepctl("metrics model.glb --method sweep,bogus", out), 2);
  // The one parser's refusal (deform/job/method_choice.h): the name, and every name accepted.
  EXPECT_NE(out.find("--method: unknown method 'bogus' (methods: dqs, lbs, sweep, sweep+contact, "
                     "sweep+features, sweep+volume)"),
            std::string::npos)
      << out;
  EXPECT_EQ(sweepctl("metrics model.glb --json --csv", out), 2);
  EXPECT_NE(out.find("not both"), std::string::npos) << out;
  EXPECT_EQ(sweepctl("metrics /nonexistent/model.glb", out), 1);
  EXPECT_NE(out.find("/nonexistent/model.glb"), std::string::npos) << out;
}

TEST(SweepctlEdit, StoresEditsInTheSweepbindAndRefusesABadFile) {
  REQUIRE_DATA();
  const fs::path dir = scratch();
  std::string out;
  ASSERT_EQ(sweepctl("bind " + kMale.string() + " -o " + (dir / "male.sweepbind").string(), out), 0)
      << out;
  std::ofstream(dir / "edits.json") << R"({"edits": [{"part": "left arm", "key": 1,
      "joint": "LeftArm", "samples": [{"angle": 120, "rotation": [0, 0, 30]}]}]})";
  ASSERT_EQ(
      sweepctl("edit " + (dir / "male.sweepbind").string() + " " + (dir / "edits.json").string(),
               out),
      0)
      << out;
  const auto bound = sweepd::io::load_sweepbind(dir / "male.sweepbind");
  ASSERT_EQ(bound.edits.edits.size(), 1u);
  EXPECT_EQ(bound.edits.edits[0].samples[0].correction.rotation.z, 30.0f);

  std::ofstream(dir / "bad.json") << R"({"edits": [{"part": "left arm", "key": 1,
      "joint": "LeftArm", "samples": [{"angle": -5}]}]})";
  EXPECT_EQ(
      sweepctl("edit " + (dir / "male.sweepbind").string() + " " + (dir / "bad.json").string(),
               out),
      1);
  EXPECT_NE(out.find("bad.json"), std::string::npos) << out;
  EXPECT_NE(out.find("must be positive"), std::string::npos) << out;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sweepctl_quality_test
