// Files the glTF tests read and write: paths into the shared real data (../shared/data) and a
// scratch directory per test that is removed afterwards.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "tests/test_paths.h"

namespace sweepd::io::testing {

inline std::filesystem::path shared_model(const std::string& relative) {
  return std::filesystem::path(SWEEPD_SHARED_DATA) / "models" / relative;
}

inline const char* kMale = "makehuman_male_cmu.glb";
inline const char* kRiggedFigure = "RiggedFigure/RiggedFigure.gltf";

// Skips the calling test (GTEST_SKIP must be used in the test body: call via this macro).
#define SWEEPD_REQUIRE_SHARED_MODEL(relative)                                                      \
  do {                                                                                             \
    if (!std::filesystem::exists(::sweepd::io::testing::shared_model(relative)))                   \
      GTEST_SKIP() << "shared test data absent: " << ::sweepd::io::testing::shared_model(relative) \
                   << " (see ../shared/data/SOURCES.md)";                                          \
  } while (0)

inline std::string read_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

inline void write_bytes(const std::filesystem::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
}

// A fresh directory named after the running test, deleted when the object goes.
class ScratchDirectory {
 public:
  ScratchDirectory() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            ("sweepd_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" +
             std::to_string(::getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDirectory() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  ScratchDirectory(const ScratchDirectory&) = delete;
  ScratchDirectory& operator=(const ScratchDirectory&) = delete;
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

}  // namespace sweepd::io::testing
