#include "server/services/vmc/vmc_receivers.h"

#include "server/log_event.h"

namespace sweepd::server {

VmcReceivers::VmcReceivers(asio::io_context& io, ModelService& models,
                           const std::vector<VmcListen>& listens) {
  for (const VmcListen& listen : listens)
    receivers_.push_back(
        std::make_unique<VmcReceiver>(io, models, listen.address, listen.port, listen.model));
}

std::vector<int> VmcReceivers::open() {
  std::vector<int> ports;
  for (const auto& receiver : receivers_) {
    ports.push_back(receiver->open());
    log_event("listening", {{"address", receiver->address()},
                            {"vmc_port", ports.back()},
                            {"stream", receiver->stream_name()}});
  }
  return ports;
}

void VmcReceivers::start() {
  for (const auto& receiver : receivers_) receiver->start();
}

void VmcReceivers::close() {
  for (const auto& receiver : receivers_) receiver->close();
}

VmcReceiver* VmcReceivers::find(std::string_view stream) const {
  for (const auto& receiver : receivers_) {
    if (receiver->stream_name() == stream) return receiver.get();
  }
  return nullptr;
}

std::string VmcReceivers::stream_names() const {
  std::string names;
  for (const auto& receiver : receivers_)
    names += (names.empty() ? "'" : ", '") + receiver->stream_name() + "'";
  return names;
}

std::vector<VmcSnapshot> VmcReceivers::snapshots() {
  std::vector<VmcSnapshot> all;
  for (const auto& receiver : receivers_) all.push_back(receiver->snapshot());
  return all;
}

}  // namespace sweepd::server
