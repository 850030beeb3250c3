#include "server/transport/auth_backoff.h"

#include <algorithm>

namespace sweepd::server {

AuthBackoff::AuthBackoff(std::uint32_t free_failures, std::chrono::milliseconds first_wait,
                         std::chrono::milliseconds max_wait, std::size_t max_addresses)
    : free_failures_(free_failures),
      first_wait_(first_wait),
      max_wait_(std::max(max_wait, first_wait)),
      max_addresses_(std::max<std::size_t>(max_addresses, 1)) {}

std::chrono::milliseconds AuthBackoff::wait(const std::string& address, Clock::time_point now) {
  const auto found = records_.find(address);
  if (found == records_.end() || now >= found->second.wait_until) {
    return std::chrono::milliseconds(0);
  }
  Record& record = found->second;
  ++record.burst.refused;
  record.last_event = now;
  // Rounded up: a client that waits what it is told is compared.
  return std::chrono::ceil<std::chrono::milliseconds>(record.wait_until - now);
}

bool AuthBackoff::failed(const std::string& address, Clock::time_point now) {
  auto found = records_.find(address);
  const bool starts = found == records_.end();
  if (starts) {
    if (records_.size() >= max_addresses_) {
      const auto quietest = std::min_element(
          records_.begin(), records_.end(),
          [](const auto& a, const auto& b) { return a.second.last_event < b.second.last_event; });
      evicted_.push_back(quietest->second.burst);
      records_.erase(quietest);
    }
    found = records_.emplace(address, Record{{address, 0, 0, now}, now, now}).first;
  }
  Record& record = found->second;
  ++record.burst.failures;
  record.last_event = now;
  if (record.burst.failures > free_failures_) {
    // first_wait × 2^(failures past the free ones − 1), at most max_wait (no overflow: capped
    // before the shift can pass it).
    const std::uint64_t doublings = record.burst.failures - free_failures_ - 1;
    std::chrono::milliseconds wait = max_wait_;
    if (doublings < 32 && (first_wait_ * (std::int64_t{1} << doublings)) < max_wait_) {
      wait = first_wait_ * (std::int64_t{1} << doublings);
    }
    record.wait_until = now + wait;
  }
  return starts;
}

bool AuthBackoff::quiet(const Record& record, Clock::time_point now) const {
  return now >= record.wait_until && now - record.last_event >= max_wait_;
}

std::vector<AuthBackoff::Burst> AuthBackoff::end_quiet_bursts(Clock::time_point now) {
  std::vector<Burst> ended = std::move(evicted_);
  evicted_.clear();
  for (auto it = records_.begin(); it != records_.end();) {
    if (quiet(it->second, now)) {
      ended.push_back(it->second.burst);
      it = records_.erase(it);
    } else {
      ++it;
    }
  }
  return ended;
}

}  // namespace sweepd::server
