#include "cli/progress_bar.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace sweepd::cli {

ProgressBar::ProgressBar(std::string title)
    : title_(std::move(title)), terminal_(isatty(STDERR_FILENO) != 0) {}

ProgressBar::~ProgressBar() {
  if (terminal_ && last_percent_ >= 0) std::fputc('\n', stderr);
}

void ProgressBar::update(double fraction, std::string_view stage) {
  const int percent = static_cast<int>(std::clamp(fraction, 0.0, 1.0) * 100.0 + 0.5);
  const bool new_stage = stage != stage_;
  if (percent == last_percent_ && !new_stage) return;
  if (terminal_) {
    constexpr int kWidth = 30;
    const int filled = percent * kWidth / 100;
    std::fprintf(stderr, "\r%s [%.*s%*s] %3d%% %-24.*s", title_.c_str(), filled,
                 "##############################", kWidth - filled, "", percent,
                 static_cast<int>(stage.size()), stage.data());
    std::fflush(stderr);
  } else if (new_stage || percent / 25 != last_percent_ / 25) {
    std::fprintf(stderr, "%s: %3d%% %.*s\n", title_.c_str(), percent,
                 static_cast<int>(stage.size()), stage.data());
  }
  last_percent_ = percent;
  stage_ = stage;
}

}  // namespace sweepd::cli
