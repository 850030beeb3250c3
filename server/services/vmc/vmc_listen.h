// VmcListen: one VMC receiver as configured (sweepd --vmc-listen ADDR[:PORT][=MODEL], read by
// server/config.cpp): the UDP address and port, and the held model its stream poses (the
// stream's name; empty until the config fills in --vmc-model's).
#pragma once

#include <string>

namespace sweepd::server {

struct VmcListen {
  std::string address;
  int port = 39539;  // VMC's receiver port; 0: a free one
  std::string model;
  bool operator==(const VmcListen&) const = default;
};

}  // namespace sweepd::server
