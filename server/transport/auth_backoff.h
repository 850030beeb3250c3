// AuthBackoff: failed authentications per peer address, so that wrong tokens cannot be tried as
// fast as the network allows (issue 49 item 1). An address may fail `free_failures` times; each
// failure after that makes it wait before its next token is compared at all: `first_wait`,
// doubling with each further failure, at most `max_wait`. A Hello that comes while its address
// waits is refused without comparing its token (the right token waits too: the server cannot
// tell an honest client from a guesser behind the same address).
//
// A burst is an address's failures and refusals until it has been quiet (no failure, no refusal,
// no wait left) for `max_wait`; then its record is forgotten and end_quiet_bursts() returns it,
// once, with its counts, for one log line per burst. At most `max_addresses` are remembered: a
// new failing address past that ends the burst that was quiet longest.
// Runs on the server's I/O thread.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace sweepd::server {

class AuthBackoff {
 public:
  using Clock = std::chrono::steady_clock;

  struct Burst {
    std::string address;
    std::uint64_t failures = 0;  // tokens compared and wrong
    std::uint64_t refused = 0;   // Hellos refused unchecked while the address waited
    Clock::time_point started{};
  };

  AuthBackoff(std::uint32_t free_failures, std::chrono::milliseconds first_wait,
              std::chrono::milliseconds max_wait, std::size_t max_addresses = 4096);

  // How long `address` must still wait before its next token is compared; zero: compare it now.
  // A nonzero answer counts as a refusal of the address's burst.
  std::chrono::milliseconds wait(const std::string& address, Clock::time_point now);
  // A token from `address` was wrong. True when this failure starts a burst.
  bool failed(const std::string& address, Clock::time_point now);
  std::vector<Burst> end_quiet_bursts(Clock::time_point now);
  std::chrono::milliseconds max_wait() const { return max_wait_; }

 private:
  struct Record {
    Burst burst;
    Clock::time_point last_event{};
    Clock::time_point wait_until{};
  };
  bool quiet(const Record& record, Clock::time_point now) const;

  std::uint32_t free_failures_;
  std::chrono::milliseconds first_wait_;
  std::chrono::milliseconds max_wait_;
  std::size_t max_addresses_;
  std::map<std::string, Record> records_;
  std::vector<Burst> evicted_;  // ended to make room, reported by the next end_quiet_bursts
};

}  // namespace sweepd::server
