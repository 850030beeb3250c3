// ProgressBar: a one-line progress bar on stderr for long sweepctl work (binding, frame ranges).
// On a terminal it redraws in place; otherwise (logs, CI) it prints a line per stage change and
// at every 25 %, so logs stay short.
#pragma once

#include <string>
#include <string_view>

namespace sweepd::cli {

class ProgressBar {
 public:
  explicit ProgressBar(std::string title);
  ~ProgressBar();  // finishes the line
  void update(double fraction, std::string_view stage);

 private:
  std::string title_;
  std::string stage_;
  bool terminal_;
  int last_percent_ = -1;
};

}  // namespace sweepd::cli
