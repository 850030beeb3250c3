// Tests for io::write_whole_file, the writer of the outputs a user names (EXR, PNG, glTF, JSON,
// contact sheets): it replaces a file whole, writes text as its bytes, writes through a FIFO in
// place (a user may name one), and names the writer, the file and the system's reason when it
// cannot write.
#include "io/files/write_whole_file.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace sweepd::io::write_whole_file_test {
namespace {

namespace fs = std::filesystem;

std::string read_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

fs::path scratch(const std::string& name) {
  return fs::temp_directory_path() /
         ("sweepd_write_whole_file_" + std::to_string(::getpid()) + "_" + name);
}

TEST(WriteWholeFile, ReplacesALongerFileWholeWithBytesOrText) {
  const fs::path file = scratch("replace.bin");
  write_whole_file(file, std::vector<std::uint8_t>(1000, 'x'), "test");
  EXPECT_EQ(fs::file_size(file), 1000u);
  write_whole_file(file, std::string_view("{\"a\": 1}\n"), "test");
  EXPECT_EQ(read_text(file), "{\"a\": 1}\n");  // truncated, not overwritten in part
  fs::remove(file);
}

TEST(WriteWholeFile, WritesThroughAFifoInPlace) {
  const fs::path fifo = scratch("fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string read;
  std::thread reader([&] { read = read_text(fifo); });
  write_whole_file(fifo, std::string_view("frame bytes"), "test");
  reader.join();
  EXPECT_EQ(read, "frame bytes");
  EXPECT_TRUE(fs::is_fifo(fifo));  // still the FIFO: nothing was renamed over it
  fs::remove(fifo);
}

TEST(WriteWholeFile, AFileThatCannotBeWrittenNamesTheWriterTheFileAndTheReason) {
  const fs::path file = scratch("no_such_directory") / "out.png";
  try {
    write_whole_file(file, std::string_view("x"), "write_png");
    FAIL() << "wrote into a directory that does not exist";
  } catch (const std::runtime_error& error) {
    EXPECT_EQ(std::string(error.what()),
              "write_png " + file.string() + ": cannot write the file (No such file or directory)");
  }
}

}  // namespace
}  // namespace sweepd::io::write_whole_file_test
