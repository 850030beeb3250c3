#include "client/frame_queue.h"

namespace sweepd::client {

FrameQueue::FrameQueue(std::vector<int> frames, int max_attempts, int threads)
    : waiting_(frames.begin(), frames.end()),
      total_(static_cast<int>(frames.size())),
      max_attempts_(max_attempts),
      threads_(threads) {}

std::optional<int> FrameQueue::take(bool wait) {
  std::unique_lock lock(mutex_);
  if (wait) changed_.wait(lock, [this] { return !waiting_.empty() || ended_locked(); });
  if (waiting_.empty()) return std::nullopt;
  const int frame = waiting_.front();
  waiting_.pop_front();
  ++attempts_[frame];
  return frame;
}

void FrameQueue::rendered(int frame) {
  const std::lock_guard lock(mutex_);
  attempts_.erase(frame);
  ++tally_.rendered;
  changed_.notify_all();
}

void FrameQueue::retry(int frame, const std::string& why) {
  const std::lock_guard lock(mutex_);
  if (attempts_[frame] >= max_attempts_) {
    ++tally_.failed;
    tally_.failures[frame] = why + " (after " + std::to_string(max_attempts_) + " attempts)";
  } else {
    ++tally_.retried;
    waiting_.push_front(frame);
  }
  changed_.notify_all();
}

void FrameQueue::fail(int frame, const std::string& why) {
  const std::lock_guard lock(mutex_);
  ++tally_.failed;
  tally_.failures[frame] = why;
  changed_.notify_all();
}

void FrameQueue::retire(const std::string& why) {
  const std::lock_guard lock(mutex_);
  if (--threads_ > 0) return;
  for (const int frame : waiting_) {
    ++tally_.failed;
    tally_.failures[frame] = why;
  }
  waiting_.clear();
  changed_.notify_all();
}

FrameQueue::Tally FrameQueue::tally() const {
  const std::lock_guard lock(mutex_);
  return tally_;
}

bool FrameQueue::ended() const {
  const std::lock_guard lock(mutex_);
  return ended_locked();
}

}  // namespace sweepd::client
