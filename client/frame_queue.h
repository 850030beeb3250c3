// FrameQueue: the frames a render client owes, shared by its threads (one per server). Frames
// go out in order; a frame whose attempt came to nothing (its server died, timed out, or said
// "later") goes back to the front, to whichever server asks next, until it has had
// max_attempts; then it fails. Every frame ends rendered or failed, and each is handed to one
// thread at a time, so no frame is written twice.
//
//   take(wait)         the next frame to send; with wait, blocks until one is waiting or every
//                      frame has ended (then nothing)
//   rendered(frame)    its file is written
//   retry(frame, why)  its attempt failed; back to the front, or failed after max_attempts
//   fail(frame, why)   it cannot be rendered anywhere (the server found the pose invalid)
//   retire(why)        a thread gives up on its server; the last one to retire fails every
//                      frame still waiting with `why`. Call it after retrying the frames the
//                      thread holds.
#pragma once

#include <condition_variable>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace sweepd::client {

class FrameQueue {
 public:
  FrameQueue(std::vector<int> frames, int max_attempts, int threads);

  std::optional<int> take(bool wait);
  void rendered(int frame);
  void retry(int frame, const std::string& why);
  void fail(int frame, const std::string& why);
  void retire(const std::string& why);

  struct Tally {
    int rendered = 0, retried = 0, failed = 0;  // retried: attempts that were repeated
    std::map<int, std::string> failures;        // frame -> why its last attempt failed
  };
  Tally tally() const;
  bool ended() const;

 private:
  bool ended_locked() const { return tally_.rendered + tally_.failed == total_; }

  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<int> waiting_;
  std::map<int, int> attempts_;  // frame -> attempts so far
  int total_, max_attempts_, threads_;
  Tally tally_;
};

}  // namespace sweepd::client
