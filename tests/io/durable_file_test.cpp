// Tests for io::write_file_durably: it replaces a file's contents whole, leaves no FILE.tmp
// behind, and names the file and the failing step when it cannot write.
#include "io/durable_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace sweepd::io {
namespace {

namespace fs = std::filesystem;

std::vector<std::uint8_t> read_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(DurableFile, ReplacesTheFileWholeAndLeavesNoTemporary) {
  const fs::path file =
      fs::temp_directory_path() / ("sweepd_durable_" + std::to_string(::getpid()) + ".bin");
  const std::vector<std::uint8_t> first(100000, 7), second = {1, 2, 3};
  write_file_durably(file, first);
  EXPECT_EQ(read_bytes(file), first);
  write_file_durably(file, second);
  EXPECT_EQ(read_bytes(file), second);
  EXPECT_FALSE(fs::exists(file.string() + ".tmp"));
  fs::remove(file);
}

TEST(DurableFile, NamesTheFileAndTheStepItCannotDo) {
  const fs::path file = fs::temp_directory_path() / "sweepd_no_such_folder" / "x.bin";
  try {
    write_file_durably(file, std::vector<std::uint8_t>{1});
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("x.bin.tmp"), std::string::npos) << message;
    EXPECT_NE(message.find("open"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace sweepd::io
