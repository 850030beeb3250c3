// Folders for a test's files under the system's temporary directory, named by the test process's
// id so that parallel tests never share one, and removed when they are no longer needed:
//   fresh_directory(name)   <tmp>/sweepd_test_<pid>_<name>, emptied and created; the caller owns it
//   ScratchDirectory(name)  a fresh_directory removed with everything in it when the object goes,
//                           unless a test failed (kept, with any daemon log, for a look)
//   process_scratch(name)   one ScratchDirectory per name for the whole test process, made on
//                           first use (and again after a test removed it) and removed at exit
//                           unless a test of the process failed
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <map>
#include <memory>
#include <string>

namespace sweepd::test {

inline std::filesystem::path fresh_directory(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("sweepd_test_" + std::to_string(getpid()) + "_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

class ScratchDirectory {
 public:
  explicit ScratchDirectory(const std::string& name) : path_(fresh_directory(name)) {}
  ~ScratchDirectory() {
    // Inside a test, that test's outcome decides; at process exit, the whole process's.
    const ::testing::UnitTest& unit = *::testing::UnitTest::GetInstance();
    const bool failed =
        unit.current_test_info() != nullptr ? ::testing::Test::HasFailure() : unit.Failed();
    if (!failed) std::filesystem::remove_all(path_);
  }
  ScratchDirectory(const ScratchDirectory&) = delete;
  ScratchDirectory& operator=(const ScratchDirectory&) = delete;

  const std::filesystem::path& path() const { return path_; }
  operator const std::filesystem::path&() const { return path_; }
  std::filesystem::path operator/(const std::filesystem::path& child) const {
    return path_ / child;
  }

 private:
  std::filesystem::path path_;
};

inline const std::filesystem::path& process_scratch(const std::string& name) {
  static std::map<std::string, std::unique_ptr<ScratchDirectory>> directories;
  std::unique_ptr<ScratchDirectory>& directory = directories[name];
  if (!directory) directory = std::make_unique<ScratchDirectory>(name);
  // Made again when a test of the process removed it, so the next test can still write there.
  std::filesystem::create_directories(directory->path());
  return directory->path();
}

}  // namespace sweepd::test
