// Tests for io::write_file_durably: it replaces a file's contents whole, leaves no FILE.tmp
// behind, and names the file and the failing step when it cannot write.
#include "io/files/durable_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace sweepd::io::durable_file_test {
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
  for (const fs::directory_entry& entry : fs::directory_iterator(file.parent_path())) {
    const std::string name = entry.path().filename().string();
    EXPECT_FALSE(name.starts_with(file.filename().string() + ".") && name.ends_with(".tmp"))
        << name;
  }
  fs::remove(file);
}

// The temporary's name carries its writer, so that writers sharing a directory never share a
// temporary, and a store can tell a crashed writer's leftovers from a live one's.
TEST(DurableFile, TemporaryNamesGiveTheirWriter) {
  const TemporaryWriter writer = temporary_writer("/store/ab.c.sweepbind.4242@node-1.lan.tmp");
  EXPECT_EQ(writer.pid, 4242);
  EXPECT_EQ(writer.host, "node-1.lan");
  EXPECT_EQ(temporary_writer("/store/index.json.tmp").pid, 0) << "an older sweepd's name";
  EXPECT_EQ(temporary_writer("/store/x.sweepbind").pid, 0) << "not a temporary";
  EXPECT_EQ(temporary_writer("/store/x.y@host.tmp").pid, 0) << "no pid before the host";
}

TEST(DurableFile, NamesTheFileAndTheStepItCannotDo) {
  const fs::path file = fs::temp_directory_path() / "sweepd_no_such_folder" / "x.bin";
  try {
    write_file_durably(file, std::vector<std::uint8_t>{1});
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("x.bin." + std::to_string(::getpid()) + "@" + this_host() + ".tmp"),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("open"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace sweepd::io::durable_file_test
