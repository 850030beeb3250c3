#include "server/services/work_budget.h"

namespace sweepd::server {

WorkReservation::~WorkReservation() { budget_.give_back(client_, bytes_); }

std::variant<std::shared_ptr<const WorkReservation>, WorkRefusal> WorkBudget::reserve(
    std::uint64_t client, std::uint64_t bytes) {
  {
    std::lock_guard lock(mutex_);
    const auto held = held_.find(client);
    const std::uint64_t client_held = held == held_.end() ? 0 : held->second;
    if (bytes > share_ || client_held > share_ - bytes) {
      ++refusals_;
      return WorkRefusal{bytes, true, share_, client_held};
    }
    if (bytes > limit_ || used_ > limit_ - bytes) {
      ++refusals_;
      return WorkRefusal{bytes, false, limit_, used_};
    }
    used_ += bytes;
    held_[client] = client_held + bytes;
  }
  return std::make_shared<const WorkReservation>(*this, client, bytes);
}

std::optional<WorkRefusal> WorkBudget::refusal_whatever_is_held(std::uint64_t bytes) {
  const bool over_share = bytes > share_;
  if (!over_share && bytes <= limit_) return std::nullopt;
  std::lock_guard lock(mutex_);
  ++refusals_;
  return WorkRefusal{bytes, over_share, over_share ? share_ : limit_, 0};
}

void WorkBudget::give_back(std::uint64_t client, std::uint64_t bytes) {
  std::lock_guard lock(mutex_);
  used_ -= bytes;
  const auto held = held_.find(client);
  if (held == held_.end()) return;  // a reservation of 0 bytes on a client holding none
  held->second -= bytes;
  if (held->second == 0) held_.erase(held);
}

std::uint64_t WorkBudget::used() const {
  std::lock_guard lock(mutex_);
  return used_;
}

std::uint64_t WorkBudget::refusals() const {
  std::lock_guard lock(mutex_);
  return refusals_;
}

}  // namespace sweepd::server
