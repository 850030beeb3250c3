// LoadError: what every reader in io/ throws for a bad file — it names the file and the reason
// (and the line, for text formats), so a user can fix the input.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

namespace sweepd::io {

class LoadError : public std::runtime_error {
 public:
  // line <= 0 means "no line number" (binary formats).
  LoadError(const std::filesystem::path& file, const std::string& reason, int line = 0);
  const std::filesystem::path& file() const { return file_; }
  const std::string& reason() const { return reason_; }  // what() without the file and line
  int line() const { return line_; }

 private:
  std::filesystem::path file_;
  std::string reason_;
  int line_;
};

}  // namespace sweepd::io
