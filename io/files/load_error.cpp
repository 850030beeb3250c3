#include "io/files/load_error.h"

namespace sweepd::io {

namespace {
std::string format(const std::filesystem::path& file, const std::string& reason, int line) {
  std::string where = file.string();
  if (line > 0) where += ":" + std::to_string(line);
  return where + ": " + reason;
}
}  // namespace

LoadError::LoadError(const std::filesystem::path& file, const std::string& reason, int line)
    : std::runtime_error(format(file, reason, line)), file_(file), reason_(reason), line_(line) {}

}  // namespace sweepd::io
