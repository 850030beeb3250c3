// VmcReceivers: the daemon's VMC receivers (--vmc-listen ADDR[:PORT][=MODEL], repeatable), a
// UDP socket each, each the stream of one held model and named by it, as a VMC "Marionette"
// (EVMC4U, Warudo's VMC receiver) listens on a port per avatar: two performers' senders, each
// sending to its own port, pose two models at once, and SubscribeStream or the viewer's
// ?stream= picks one by its model's name. A sender's own frames go only to its receiver's
// stream: the bones one sender has sent never mix into another's.
//
// open() binds every socket in order (throws std::runtime_error naming the address and why)
// and returns the bound ports; start() begins reading. All on the I/O thread.
#pragma once

#include <asio.hpp>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "server/models/model_service.h"
#include "server/services/vmc/vmc_listen.h"
#include "server/services/vmc/vmc_receiver.h"

namespace sweepd::server {

class VmcReceivers {
 public:
  VmcReceivers(asio::io_context& io, ModelService& models, const std::vector<VmcListen>& listens);

  bool empty() const { return receivers_.empty(); }
  std::vector<int> open();
  void start();
  void close();

  // The receiver whose stream is named `stream`, or null.
  VmcReceiver* find(std::string_view stream) const;
  // The streams' names, in --vmc-listen's order, quoted and comma-separated: "'a', 'b'".
  std::string stream_names() const;
  std::vector<VmcSnapshot> snapshots();

 private:
  std::vector<std::unique_ptr<VmcReceiver>> receivers_;
};

}  // namespace sweepd::server
