#include "console/progress_bar.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace sweepd::console {

ProgressBar::ProgressBar(std::string title)
    : title_(std::move(title)), terminal_(isatty(STDERR_FILENO) != 0) {}

ProgressBar::~ProgressBar() {
  if (terminal_ && last_percent_ >= 0) std::fputc('\n', stderr);
}

void ProgressBar::update(double fraction, std::string_view stage, std::string_view detail) {
  fraction = std::clamp(fraction, 0.0, 1.0);
  if (last_percent_ < 0) {
    first_fraction_ = fraction;
    first_update_ = Clock::now();
  }
  const int percent = static_cast<int>(fraction * 100.0 + 0.5);
  const bool new_stage = stage != stage_;
  if (percent == last_percent_ && !new_stage && detail.empty()) return;
  if (terminal_) {
    constexpr int kWidth = 30;
    const int filled = percent * kWidth / 100;
    const double seconds = std::chrono::duration<double>(Clock::now() - first_update_).count();
    const double done = fraction - first_fraction_;
    std::string eta;
    if (done > 0.0 && fraction < 1.0)
      eta =
          "ETA " + std::to_string(static_cast<int>(seconds * (1.0 - fraction) / done + 0.5)) + " s";
    std::fprintf(stderr, "\r%s [%.*s%*s] %3d%% %.*s %.*s %s    ", title_.c_str(), filled,
                 "##############################", kWidth - filled, "", percent,
                 static_cast<int>(stage.size()), stage.data(), static_cast<int>(detail.size()),
                 detail.data(), eta.c_str());
    std::fflush(stderr);
  } else if (new_stage || percent / 25 != last_percent_ / 25) {
    std::fprintf(stderr, "%s: %3d%% %.*s\n", title_.c_str(), percent,
                 static_cast<int>(stage.size()), stage.data());
  }
  last_percent_ = percent;
  stage_ = stage;
}

}  // namespace sweepd::console
