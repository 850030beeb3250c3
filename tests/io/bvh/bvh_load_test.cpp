// Tests for io::load_bvh / io::parse_bvh and the motion::Clip accessors.
#include "io/bvh/bvh_load.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "io/files/load_error.h"

namespace sweepd::io::bvh_load_test {
namespace {

namespace fs = std::filesystem;

fs::path shared_clip(const char* name) { return fs::path(SWEEPD_SHARED_DATA) / "motion" / name; }

// A directory of its own for the files a test writes, removed afterwards.
class ScratchDirectory {
 public:
  ScratchDirectory()
      : path_(fs::temp_directory_path() /
              ("sweepd_bvh_test_" + std::to_string(::getpid()) + "_" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name())) {
    fs::create_directories(path_);
  }
  ~ScratchDirectory() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  fs::path write(const std::string& name, const std::string& text) const {
    const fs::path file = path_ / name;
    std::ofstream(file, std::ios::binary) << text;
    return file;
  }

 private:
  fs::path path_;
};

// A small valid clip: 2 joints, 9 channels, 2 frames. Tests break it one line at a time, so the
// line numbers matter: line 9 is Chest's CHANNELS, lines 19 and 20 are the data rows.
const std::vector<std::string> kSmallClipLines = {
    "HIERARCHY",                                                                 // 1
    "ROOT Hips",                                                                 // 2
    "{",                                                                         // 3
    "\tOFFSET 0 0 0",                                                            // 4
    "\tCHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation",  // 5
    "\tJOINT Chest",                                                             // 6
    "\t{",                                                                       // 7
    "\t\tOFFSET 0 5 0",                                                          // 8
    "\t\tCHANNELS 3 Zrotation Yrotation Xrotation",                              // 9
    "\t\tEnd Site",                                                              // 10
    "\t\t{",                                                                     // 11
    "\t\t\tOFFSET 0 3 0",                                                        // 12
    "\t\t}",                                                                     // 13
    "\t}",                                                                       // 14
    "}",                                                                         // 15
    "MOTION",                                                                    // 16
    "Frames: 2",                                                                 // 17
    "Frame Time: 0.0333333",                                                     // 18
    "1 2 3 10 20 30 40 50 60",                                                   // 19
    "4\t5 6 11 21 31 41 51 61 ",                                                 // 20
};

std::string join_lines(const std::vector<std::string>& lines, const std::string& end = "\n") {
  std::string text;
  for (const std::string& line : lines) text += line + end;
  return text;
}

// The small clip with 1-based line `line` replaced by `replacement` (which may hold '\n').
std::string small_clip_with(int line, const std::string& replacement) {
  std::vector<std::string> lines = kSmallClipLines;
  lines.at(line - 1) = replacement;
  return join_lines(lines);
}

// Composes rotations about the coordinate axes, left to right, angles in degrees.
glm::quat compose(const std::vector<std::pair<char, float>>& rotations) {
  glm::quat q = glm::identity<glm::quat>();
  for (const auto& [axis, degrees] : rotations) {
    const glm::vec3 unit(axis == 'X' ? 1.0f : 0.0f, axis == 'Y' ? 1.0f : 0.0f,
                         axis == 'Z' ? 1.0f : 0.0f);
    q = q * glm::angleAxis(glm::radians(degrees), unit);
  }
  return q;
}

void expect_vec3_near(const glm::vec3& actual, const glm::vec3& expected, float tolerance) {
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(actual[i], expected[i], tolerance) << "component " << i;
}

// q and -q are the same rotation; compare against whichever sign is closer.
void expect_same_rotation(const glm::quat& actual, const glm::quat& expected, float tolerance) {
  const float sign = glm::dot(actual, expected) < 0.0f ? -1.0f : 1.0f;
  for (int i = 0; i < 4; ++i)
    EXPECT_NEAR(actual[i], sign * expected[i], tolerance) << "q[" << i << "]";
}

// The numbers on one data line of a file, read with iostreams (independently of the loader).
std::vector<float> numbers_on_line(const fs::path& file, int line_number) {
  std::ifstream in(file);
  std::string line;
  for (int i = 0; i < line_number; ++i) std::getline(in, line);
  std::istringstream numbers(line);
  std::vector<float> values;
  for (float v; numbers >> v;) values.push_back(v);
  return values;
}

// The LoadError that load() throws; records a test failure and gives nothing when none is thrown.
template <class Load>
std::optional<LoadError> load_error_of(Load load) {
  try {
    load();
  } catch (const LoadError& error) {
    return error;
  }
  ADD_FAILURE() << "loaded without an error";
  return std::nullopt;
}

// What SOURCES.md states about both CMU clips.
void check_cmu_clip(const fs::path& file, int frames) {
  if (!fs::exists(file)) GTEST_SKIP() << "shared data missing: " << file;
  // Load speed is a benchmark matter (bench/), never a test assertion.
  const motion::Clip motion = load_bvh(file);

  const std::vector<std::string> names = {
      "Hips",         "LHipJoint",      "LeftUpLeg",    "LeftLeg",         "LeftFoot",
      "LeftToeBase",  "RHipJoint",      "RightUpLeg",   "RightLeg",        "RightFoot",
      "RightToeBase", "LowerBack",      "Spine",        "Spine1",          "Neck",
      "Neck1",        "Head",           "LeftShoulder", "LeftArm",         "LeftForeArm",
      "LeftHand",     "LeftFingerBase", "LFingers",     "LThumb",          "RightShoulder",
      "RightArm",     "RightForeArm",   "RightHand",    "RightFingerBase", "RFingers",
      "RThumb"};
  ASSERT_EQ(motion.joints.size(), names.size());
  int end_sites = 0;
  for (std::size_t j = 0; j < names.size(); ++j) {
    EXPECT_EQ(motion.joints[j].name, names[j]);
    EXPECT_LT(motion.joints[j].parent, static_cast<int>(j)) << "parents come first";
    end_sites += motion.joints[j].end_site.has_value();
  }
  EXPECT_EQ(motion.joints[0].parent, -1);
  EXPECT_EQ(end_sites, 7);
  EXPECT_EQ(motion.channel_count, 96);
  EXPECT_EQ(motion.frame_count, frames);
  EXPECT_EQ(motion.header_frame_count, frames);
  EXPECT_EQ(motion.values.size(), static_cast<std::size_t>(frames) * 96);
  // The file says 0.0083333 s: 120 fps up to the 5 digits written.
  EXPECT_NEAR(motion.frames_per_second(), 120.0f, 1e-3f);
  EXPECT_TRUE(motion.warnings.empty()) << motion.warnings.front();

  using enum motion::Channel;
  const std::vector<motion::Channel> root = {kXposition, kYposition, kZposition,
                                             kZrotation, kYrotation, kXrotation};
  const std::vector<motion::Channel> zyx = {kZrotation, kYrotation, kXrotation};
  EXPECT_EQ(motion.joints[0].channels, root);
  for (std::size_t j = 1; j < motion.joints.size(); ++j) {
    EXPECT_EQ(motion.joints[j].channels, zyx) << motion.joints[j].name;
  }

  // First and last data rows against an iostream read of the same lines; rows start 3 lines
  // after the MOTION line.
  std::ifstream in(file);
  std::string line;
  int motion_line = 0;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.rfind("MOTION", 0) == 0) motion_line = n;
  }
  ASSERT_GT(motion_line, 0);
  const std::array<int, 2> checked_frames = {0, frames - 1};
  for (int frame : checked_frames) {
    const std::vector<float> expected = numbers_on_line(file, motion_line + 3 + frame);
    ASSERT_EQ(expected.size(), 96u);
    const std::span<const float> row = motion.frame(frame);
    // Both parsers round the same decimal text to the nearest float.
    for (int c = 0; c < 96; ++c) EXPECT_FLOAT_EQ(row[c], expected[c]) << "frame " << frame;
  }
}

TEST(BvhLoad, CmuClip0101MatchesSources) { check_cmu_clip(shared_clip("cmu_01_01.bvh"), 2752); }

TEST(BvhLoad, CmuClip0103MatchesSources) { check_cmu_clip(shared_clip("cmu_01_03.bvh"), 4511); }

TEST(BvhLoad, RotationChannelsComposeInFileOrder) {
  // One joint per rotation order, each with different angles in each of two frames.
  const std::array<std::string, 6> orders = {"XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX"};
  std::string text = "HIERARCHY\n";
  for (std::size_t j = 0; j < orders.size(); ++j) {
    text += (j == 0 ? "ROOT " : "JOINT ") + orders[j] + "\n{\nOFFSET 0 1 0\nCHANNELS 3";
    for (char axis : orders[j]) text += std::string(" ") + axis + "rotation";
    text += "\n";
  }
  for (std::size_t j = 0; j < orders.size(); ++j) text += "}\n";
  text += "MOTION\nFrames: 2\nFrame Time: 0.01\n";
  auto angle = [](int frame, std::size_t joint, int c) {
    return -170.0f + 23.0f * static_cast<float>(frame) + 37.0f * static_cast<float>(joint) +
           51.0f * static_cast<float>(c);
  };
  for (int frame = 0; frame < 2; ++frame) {
    for (std::size_t j = 0; j < orders.size(); ++j) {
      for (int c = 0; c < 3; ++c) text += std::to_string(angle(frame, j, c)) + " ";
    }
    text += "\n";
  }

  const motion::Clip motion = parse_bvh(text, "orders.bvh");
  ASSERT_EQ(motion.joints.size(), orders.size());
  for (int frame = 0; frame < 2; ++frame) {
    for (std::size_t j = 0; j < orders.size(); ++j) {
      const std::string& order = orders[j];
      const glm::quat expected = compose({{order[0], angle(frame, j, 0)},
                                          {order[1], angle(frame, j, 1)},
                                          {order[2], angle(frame, j, 2)}});
      SCOPED_TRACE(order + " frame " + std::to_string(frame));
      // Same float operations in a different code path: agreement to float rounding.
      expect_same_rotation(motion.local_rotation(static_cast<int>(j), frame), expected, 1e-6f);
    }
  }
}

TEST(BvhLoad, RotationConventionIsRightHandedColumnVectors) {
  // Checked against geometry, not glm: Rz(90) turns +X into +Y, and "Xrotation Yrotation" with
  // 90 and 90 is Rx * Ry, which turns +X into -Z (by Ry) and then into +Y (by Rx).
  const motion::Clip motion = parse_bvh(
      "HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 1 Zrotation\n"
      "JOINT B\n{\nOFFSET 0 0 0\nCHANNELS 2 Xrotation Yrotation\n}\n}\n"
      "MOTION\nFrames: 1\nFrame Time: 0.01\n90 90 90\n",
      "convention.bvh");
  // Rotating a unit vector in float: exact up to ~1e-7 per component.
  expect_vec3_near(motion.local_rotation(0, 0) * glm::vec3(1, 0, 0), {0, 1, 0}, 1e-6f);
  expect_vec3_near(motion.local_rotation(1, 0) * glm::vec3(1, 0, 0), {0, 1, 0}, 1e-6f);
}

TEST(BvhLoad, AnyChannelSubsetAndOrder) {
  // Positions and rotations interleaved, a 2-channel joint and a joint without channels.
  const motion::Clip motion = parse_bvh(
      "HIERARCHY\nROOT A\n{\nOFFSET 1 2 3\n"
      "CHANNELS 6 Yrotation Zposition Xrotation Xposition Zrotation Yposition\n"
      "JOINT B\n{\nOFFSET 0 4 0\nCHANNELS 2 Xposition Zrotation\n"
      "JOINT C\n{\nOFFSET 0 0 7\nCHANNELS 0\nEnd Site\n{\nOFFSET 0 0 1\n}\n}\n}\n}\n"
      "MOTION\nFrames: 1\nFrame Time: 0.01\n10 20 30 40 50 60 70 80\n",
      "subset.bvh");
  ASSERT_EQ(motion.channel_count, 8);
  EXPECT_EQ(motion.joints[1].channel_offset, 6);
  EXPECT_EQ(motion.joints[2].channel_offset, 8);
  // Sums and products of small integers: exact in float; rotations to float rounding.
  expect_vec3_near(motion.local_translation(0, 0), {1 + 40, 2 + 60, 3 + 20}, 0.0f);
  expect_same_rotation(motion.local_rotation(0, 0), compose({{'Y', 10}, {'X', 30}, {'Z', 50}}),
                       1e-6f);
  expect_vec3_near(motion.local_translation(1, 0), {70, 4, 0}, 0.0f);
  expect_same_rotation(motion.local_rotation(1, 0), compose({{'Z', 80}}), 1e-6f);
  expect_vec3_near(motion.local_translation(2, 0), {0, 0, 7}, 0.0f);
  expect_same_rotation(motion.local_rotation(2, 0), glm::identity<glm::quat>(), 0.0f);
  ASSERT_TRUE(motion.joints[2].end_site.has_value());
  expect_vec3_near(*motion.joints[2].end_site, {0, 0, 1}, 0.0f);

  // local_pose fills caller buffers with the same values as the per-joint calls.
  std::vector<glm::quat> rotations(3);
  std::vector<glm::vec3> translations(3);
  motion.local_pose(0, rotations, translations);
  for (int j = 0; j < 3; ++j) {
    expect_same_rotation(rotations[j], motion.local_rotation(j, 0), 0.0f);
    expect_vec3_near(translations[j], motion.local_translation(j, 0), 0.0f);
  }
}

TEST(BvhLoad, SeveralRootsAndZeroFramesLoad) {
  const motion::Clip motion = parse_bvh(
      "HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 1 Xrotation\n}\n"
      "ROOT B\n{\nOFFSET 1 0 0\nCHANNELS 1 Yposition\n}\n"
      "MOTION\nFrames: 0\nFrame Time: 0.5\n",
      "empty_clip.bvh");
  ASSERT_EQ(motion.joints.size(), 2u);
  EXPECT_EQ(motion.joints[1].parent, -1);
  EXPECT_EQ(motion.joints[1].channel_offset, 1);
  EXPECT_EQ(motion.frame_count, 0);
  EXPECT_TRUE(motion.values.empty());
  EXPECT_TRUE(motion.warnings.empty());
  EXPECT_FLOAT_EQ(motion.frames_per_second(), 2.0f);  // 1 / 0.5, exact in float
}

TEST(BvhLoad, LengthScaleAppliesToOffsetsAndPositionsOnly) {
  const std::string text = join_lines(kSmallClipLines);
  const motion::Clip plain = parse_bvh(text, "small.bvh");
  const float scale = 0.056444f;  // CMU units to metres
  const motion::Clip scaled = parse_bvh(text, "small.bvh", {.length_scale = scale});
  ASSERT_EQ(plain.joints.size(), 2u);
  // One float multiplication each: within a relative 1e-6.
  expect_vec3_near(scaled.joints[1].offset, glm::vec3(0, 5, 0) * scale, 1e-6f);
  expect_vec3_near(*scaled.joints[1].end_site, glm::vec3(0, 3, 0) * scale, 1e-6f);
  for (int frame = 0; frame < 2; ++frame) {
    expect_vec3_near(scaled.local_translation(0, frame), plain.local_translation(0, frame) * scale,
                     1e-6f);
    expect_vec3_near(scaled.local_translation(1, frame), plain.local_translation(1, frame) * scale,
                     1e-6f);
    for (int j = 0; j < 2; ++j) {
      expect_same_rotation(scaled.local_rotation(j, frame), plain.local_rotation(j, frame), 0.0f);
    }
  }
  expect_vec3_near(plain.local_translation(0, 1), {4, 5, 6}, 0.0f);  // read exactly

  for (float bad : {0.0f, -1.0f, NAN, INFINITY}) {
    EXPECT_THROW(parse_bvh(text, "small.bvh", {.length_scale = bad}), LoadError) << bad;
  }
}

struct MalformedCase {
  const char* what;
  std::string text;
  int line;              // where the error must point
  const char* mentions;  // a piece of the message that names the problem
};

std::vector<MalformedCase> malformed_cases() {
  std::vector<std::string> no_hierarchy_body = kSmallClipLines;
  no_hierarchy_body.erase(no_hierarchy_body.begin() + 1, no_hierarchy_body.begin() + 15);
  std::vector<std::string> up_to_hierarchy(kSmallClipLines.begin(), kSmallClipLines.begin() + 15);
  return {
      {"empty file", "", 1, "empty"},
      {"missing HIERARCHY", small_clip_with(1, ""), 2, "missing HIERARCHY"},
      {"missing ROOT", small_clip_with(2, "JOINT Hips"), 2, "missing ROOT"},
      {"empty hierarchy", join_lines(no_hierarchy_body), 2, "empty hierarchy"},
      {"missing MOTION line", small_clip_with(16, ""), 17, "missing MOTION"},
      {"file ends after hierarchy", join_lines(up_to_hierarchy), 15, "missing MOTION"},
      {"joint left open", small_clip_with(14, ""), 16, "unbalanced braces"},
      {"extra closing brace", small_clip_with(15, "}\n}"), 16, "unbalanced braces"},
      {"missing brace after name", small_clip_with(7, ""), 8, "expected '{'"},
      {"unknown keyword", small_clip_with(9, "\t\tROTATION 3 Zrotation Yrotation Xrotation"), 9,
       "unknown keyword 'ROTATION'"},
      {"bad channel name", small_clip_with(9, "\t\tCHANNELS 3 Zrotation Wrotation Xrotation"), 9,
       "bad channel name 'Wrotation'"},
      {"channel count not a number", small_clip_with(9, "\t\tCHANNELS three Zrotation"), 9,
       "CHANNELS count"},
      {"offset not a number", small_clip_with(8, "\t\tOFFSET 0 five 0"), 8, "'five'"},
      {"offset missing", small_clip_with(8, ""), 14, "has no OFFSET"},
      {"missing Frames:", small_clip_with(17, ""), 18, "missing 'Frames:'"},
      {"Frames: not a number", small_clip_with(17, "Frames: many"), 17, "'many'"},
      {"missing Frame Time:", small_clip_with(18, ""), 19, "missing 'Frame Time:'"},
      {"zero frame time", small_clip_with(18, "Frame Time: 0"), 18, "positive"},
      {"negative frame time", small_clip_with(18, "Frame Time: -0.01"), 18, "positive"},
      {"non-numeric value", small_clip_with(20, "4 5 6 11 21 x 41 51 61"), 20,
       "frame 1 (counting from 0), value 6 (Xrotation of joint 'Hips') is not a number: 'x'"},
      {"NaN value", small_clip_with(19, "1 2 3 10 20 30 nan 50 60"), 19, "NaN or infinite"},
      {"Inf value", small_clip_with(20, "4 5 6 11 21 31 41 -inf 61"), 20, "NaN or infinite"},
      {"short row", small_clip_with(19, "1 2 3 10 20 30 40 50"), 19,
       "frame 0 (counting from 0) has 8 values, expected 9"},
      {"long row", small_clip_with(20, "4 5 6 11 21 31 41 51 61 71"), 20,
       "frame 1 (counting from 0) has 10 values, expected 9"},
  };
}

TEST(BvhLoad, MalformedFilesNameLineAndProblem) {
  for (const MalformedCase& bad : malformed_cases()) {
    SCOPED_TRACE(bad.what);
    const std::optional<LoadError> error =
        load_error_of([&] { parse_bvh(bad.text, "broken.bvh"); });
    if (!error) continue;
    EXPECT_EQ(error->line(), bad.line) << error->what();
    EXPECT_EQ(error->file(), fs::path("broken.bvh"));
    EXPECT_NE(std::string(error->what()).find(bad.mentions), std::string::npos)
        << error->what() << "\n  should mention: " << bad.mentions;
  }
}

TEST(BvhLoad, FrameCountMismatchWarnsAndKeepsRows) {
  for (int header : {1, 3}) {
    const motion::Clip motion =
        parse_bvh(small_clip_with(17, "Frames: " + std::to_string(header)), "count.bvh");
    EXPECT_EQ(motion.frame_count, 2);
    EXPECT_EQ(motion.header_frame_count, header);
    EXPECT_EQ(motion.values.size(), 18u);
    ASSERT_EQ(motion.warnings.size(), 1u);
    EXPECT_NE(motion.warnings[0].find("disagrees with the 2 data rows"), std::string::npos)
        << motion.warnings[0];
  }
}

TEST(BvhLoad, DuplicateJointNamesWarn) {
  const motion::Clip motion = parse_bvh(small_clip_with(6, "\tJOINT Hips"), "duplicate.bvh");
  ASSERT_EQ(motion.warnings.size(), 1u);
  EXPECT_NE(motion.warnings[0].find("line 6: duplicate joint name 'Hips'"), std::string::npos)
      << motion.warnings[0];
}

TEST(BvhLoad, CrlfFileLoadsIdentically) {
  ScratchDirectory scratch;
  const motion::Clip lf = load_bvh(scratch.write("lf.bvh", join_lines(kSmallClipLines)));
  const motion::Clip crlf =
      load_bvh(scratch.write("crlf.bvh", join_lines(kSmallClipLines, "\r\n")));
  ASSERT_EQ(crlf.joints.size(), lf.joints.size());
  for (std::size_t j = 0; j < lf.joints.size(); ++j) {
    EXPECT_EQ(crlf.joints[j].name, lf.joints[j].name);
    EXPECT_EQ(crlf.joints[j].parent, lf.joints[j].parent);
    EXPECT_EQ(crlf.joints[j].offset, lf.joints[j].offset);
    EXPECT_EQ(crlf.joints[j].channels, lf.joints[j].channels);
    EXPECT_EQ(crlf.joints[j].end_site, lf.joints[j].end_site);
  }
  EXPECT_EQ(crlf.frame_count, 2);
  EXPECT_EQ(crlf.frame_time, lf.frame_time);
  EXPECT_EQ(crlf.values, lf.values);
  EXPECT_TRUE(crlf.warnings.empty());

  // Errors point at the same line with either line ending.
  std::vector<std::string> short_row = kSmallClipLines;
  short_row[19] = "4 5 6";
  const fs::path file = scratch.write("crlf_short.bvh", join_lines(short_row, "\r\n"));
  const std::optional<LoadError> error = load_error_of([&] { load_bvh(file); });
  ASSERT_TRUE(error.has_value());
  EXPECT_EQ(error->line(), 20) << error->what();
}

TEST(BvhLoad, MissingFileIsALoadError) {
  const fs::path missing = fs::temp_directory_path() / "sweepd_no_such_clip.bvh";
  const std::optional<LoadError> error = load_error_of([&] { load_bvh(missing); });
  ASSERT_TRUE(error.has_value());
  EXPECT_EQ(error->file(), missing);
  EXPECT_NE(std::string(error->what()).find("no such file"), std::string::npos) << error->what();
}

}  // namespace
}  // namespace sweepd::io::bvh_load_test
