// WorkBudget: one limit on the working memory requests hold while they run — position maps'
// render targets, read-back and EXR buffers, contact sheets' pictures and PNG encoding, poses'
// reply frames, clip uploads' decoded data — and a share of it that no one client may pass, so
// that a few clients asking for the largest valid work at once cannot take the daemon past the
// memory an operator allowed (issue 49 item 2). A request's bytes are estimated at intake (an
// upper bound: server/handlers/work_size.h) and reserved for the work's life; a request that does
// not fit now is refused at once, as the buffer budget refuses (nothing waits). Thread-safe.
//
// reserve(client, bytes): a reservation holding the bytes until its last copy is destroyed, or
//   the WorkRefusal saying which limit they pass (the budget's or the client's share) and what
//   is free of it now (work_size.h's describe says it in an error).
// refusal_whatever_is_held(bytes): for work asked for now and done later, again and again (a
//   stream's frames): what could never fit is refused when it is asked.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <unordered_map>
#include <variant>

namespace sweepd::server {

class WorkBudget;

// Bytes taken from a WorkBudget; given back when destroyed.
class WorkReservation {
 public:
  WorkReservation(WorkBudget& budget, std::uint64_t client, std::uint64_t bytes)
      : budget_(budget), client_(client), bytes_(bytes) {}
  ~WorkReservation();
  WorkReservation(const WorkReservation&) = delete;
  WorkReservation& operator=(const WorkReservation&) = delete;
  std::uint64_t bytes() const { return bytes_; }

 private:
  WorkBudget& budget_;
  std::uint64_t client_;
  std::uint64_t bytes_;
};

struct WorkRefusal {
  std::uint64_t bytes = 0;   // asked for
  bool over_share = false;   // the client's share, else the whole budget
  std::uint64_t limit = 0;   // that share or budget
  std::uint64_t in_use = 0;  // of it, held now
};

class WorkBudget {
 public:
  WorkBudget(std::uint64_t limit_bytes, std::uint64_t client_share_bytes)
      : limit_(limit_bytes), share_(client_share_bytes) {}

  std::variant<std::shared_ptr<const WorkReservation>, WorkRefusal> reserve(std::uint64_t client,
                                                                            std::uint64_t bytes);

  // The refusal a request of `bytes` gets however little is held (past a client's share or the
  // whole budget), counted as a refusal; nullopt when it fits once other work is done.
  std::optional<WorkRefusal> refusal_whatever_is_held(std::uint64_t bytes);

  std::uint64_t limit() const { return limit_; }
  std::uint64_t client_share() const { return share_; }
  std::uint64_t used() const;
  std::uint64_t refusals() const;

 private:
  friend class WorkReservation;
  void give_back(std::uint64_t client, std::uint64_t bytes);

  const std::uint64_t limit_, share_;
  mutable std::mutex mutex_;
  std::uint64_t used_ = 0;
  std::uint64_t refusals_ = 0;
  std::unordered_map<std::uint64_t, std::uint64_t> held_;  // per client, only while nonzero
};

}  // namespace sweepd::server
