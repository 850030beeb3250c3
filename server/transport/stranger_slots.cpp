#include "server/transport/stranger_slots.h"

#include <algorithm>
#include <stdexcept>

namespace sweepd::server {

StrangerSlots::StrangerSlots(std::size_t total, std::size_t per_address)
    : total_(total), per_address_(std::min(per_address, total)) {
  if (total_ == 0 || per_address_ == 0) {
    throw std::invalid_argument("StrangerSlots needs room for at least one stranger");
  }
}

std::vector<StrangerSlots::Shed> StrangerSlots::admit(std::uint64_t id,
                                                      const std::string& address) {
  std::vector<Shed> shed;
  if (held_by(address) >= per_address_) shed.push_back({shed_oldest_of(address), true});
  if (address_of_.size() >= total_) {
    const auto crowding =
        std::max_element(count_of_.begin(), count_of_.end(),
                         [](const auto& a, const auto& b) { return a.second < b.second; });
    shed.push_back({shed_oldest_of(crowding->first), false});
  }
  address_of_.emplace(id, address);
  ++count_of_[address];
  return shed;
}

void StrangerSlots::forget(const std::function<bool(std::uint64_t id)>& keep) {
  std::vector<std::uint64_t> gone;
  for (const auto& [id, address] : address_of_)
    if (!keep(id)) gone.push_back(id);
  for (const std::uint64_t id : gone) erase(id);
}

std::size_t StrangerSlots::held_by(const std::string& address) const {
  const auto found = count_of_.find(address);
  return found == count_of_.end() ? 0 : found->second;
}

std::uint64_t StrangerSlots::shed_oldest_of(const std::string& address) {
  const auto oldest = std::find_if(address_of_.begin(), address_of_.end(),
                                   [&](const auto& entry) { return entry.second == address; });
  const std::uint64_t id = oldest->first;
  erase(id);
  return id;
}

void StrangerSlots::erase(std::uint64_t id) {
  const auto found = address_of_.find(id);
  if (found == address_of_.end()) return;
  const auto count = count_of_.find(found->second);
  if (--count->second == 0) count_of_.erase(count);
  address_of_.erase(found);
}

}  // namespace sweepd::server
