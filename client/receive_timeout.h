// ReceiveTimeout: a client connection waited longer than its receive timeout for the server's
// next bytes (client::Connection::set_receive_timeout). The connection is unusable after it.
#pragma once

#include <stdexcept>

namespace sweepd::client {

class ReceiveTimeout : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace sweepd::client
