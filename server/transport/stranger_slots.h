// StrangerSlots: the connections that have not yet authenticated (strangers), by peer address,
// and which of them to shed when a new one would pass its quota (issue 49 item 1). A stranger
// holds a socket, a read buffer and a Hello deadline but no member's slot: authenticated
// connections have their own limit (--max-connections), so no number of strangers can keep an
// honest client with the token out.
//
// admit(id, address): records a new stranger and returns the strangers to shed, and for which
// quota, so that at most `per_address` strangers share an address and at most `total` are held
// in all: past the address's quota its own oldest stranger goes; past the total, the oldest
// stranger of the address that holds the most (a crowding address pays first). The newcomer
// itself is never shed: the oldest stranger has had the longest to say Hello, and an honest
// client that connected just now is about to. `forget(keep)` drops every stranger for which
// `keep` says no (it authenticated, was cut, or closed); the server calls it before each admit.
// Runs on the server's I/O thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace sweepd::server {

class StrangerSlots {
 public:
  struct Shed {
    std::uint64_t id = 0;
    bool address_full = false;  // its address's quota; else the total
  };

  StrangerSlots(std::size_t total, std::size_t per_address);

  std::vector<Shed> admit(std::uint64_t id, const std::string& address);
  void forget(const std::function<bool(std::uint64_t id)>& keep);
  std::size_t size() const { return address_of_.size(); }
  std::size_t held_by(const std::string& address) const;
  std::size_t per_address() const { return per_address_; }
  std::size_t total() const { return total_; }

 private:
  // Sheds the oldest stranger of `address` (it holds at least one).
  std::uint64_t shed_oldest_of(const std::string& address);
  void erase(std::uint64_t id);

  std::size_t total_;
  std::size_t per_address_;
  std::map<std::uint64_t, std::string> address_of_;  // ids rise with age: oldest first
  std::map<std::string, std::size_t> count_of_;
};

}  // namespace sweepd::server
