// Tests for io::load_joint_name_map_json (the --bvh-map file): pairs and left-out joints come
// through by name; a file of the wrong shape is a LoadError naming the file and the problem.
#include "io/json/joint_name_map_json.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "io/files/load_error.h"

namespace sweepd::io {
namespace {

namespace fs = std::filesystem;

// A file of its own for a name map, removed afterwards.
class NameMapFile {
 public:
  explicit NameMapFile(const std::string& text)
      : path_(fs::temp_directory_path() /
              ("sweepd_name_map_" + std::to_string(::getpid()) + "_" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".json")) {
    std::ofstream(path_) << text;
  }
  ~NameMapFile() { fs::remove(path_); }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

TEST(JointNameMapJson, PairsAndLeftOutJointsComeThroughByName) {
  const NameMapFile file(R"({"LFingers": "LeftHandFinger1", "Head": null})");
  const motion::JointNameMap map = load_joint_name_map_json(file.path());
  EXPECT_EQ(map.source, file.path().string());
  ASSERT_EQ(map.pairs.size(), 2u);
  EXPECT_EQ(map.pairs[0].clip_joint, "Head");  // by name: nlohmann's objects are sorted
  EXPECT_FALSE(map.pairs[0].model_joint.has_value());
  EXPECT_EQ(map.pairs[1].clip_joint, "LFingers");
  EXPECT_EQ(map.pairs[1].model_joint, "LeftHandFinger1");
}

TEST(JointNameMapJson, BadFilesNameTheFileAndTheProblem) {
  const std::pair<const char*, const char*> cases[] = {{R"({"Hips": 3})", "Hips"},
                                                       {R"(["Hips"])", "expected an object"},
                                                       {R"({"Hips": )", "not valid JSON"}};
  for (const auto& [text, expected] : cases) {
    const NameMapFile file(text);
    try {
      load_joint_name_map_json(file.path());
      ADD_FAILURE() << "no error for " << text;
    } catch (const LoadError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(file.path().filename().string()), std::string::npos) << message;
      EXPECT_NE(message.find(expected), std::string::npos) << message;
    }
  }
}

}  // namespace
}  // namespace sweepd::io
