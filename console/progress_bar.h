// ProgressBar: the one progress line on stderr of sweepd's command-line programs (sweepctl's
// binding and frame ranges, render_frames' frames). On a terminal it redraws in place with an
// ETA; otherwise (logs, CI) it prints a line per stage change and at every 25 %, so logs stay
// short.
//
//   update(fraction, stage, detail)  fraction in [0, 1] (clamped); stage names the step (a new
//                                    stage starts a new log line); detail is shown on the
//                                    terminal only (e.g. "12/240 frames, 3.1 frames/s")
// The ETA is the time left at the rate since the first update, so work skipped before it
// (frames already on disk) does not make it optimistic.
#pragma once

#include <chrono>
#include <string>
#include <string_view>

namespace sweepd::console {

class ProgressBar {
 public:
  explicit ProgressBar(std::string title);
  ~ProgressBar();  // finishes the line
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;
  void update(double fraction, std::string_view stage, std::string_view detail = {});

 private:
  using Clock = std::chrono::steady_clock;
  std::string title_;
  std::string stage_;
  bool terminal_;
  int last_percent_ = -1;
  double first_fraction_ = 0.0;
  Clock::time_point first_update_;
};

}  // namespace sweepd::console
