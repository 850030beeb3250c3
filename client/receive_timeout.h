// ReceiveTimeout: a client connection waited longer than its receive timeout for the server's
// next bytes (client::Connection::set_receive_timeout). The connection is unusable after it,
// so it is one way of losing it (client/connection_lost.h).
#pragma once

#include "client/connection_lost.h"

namespace sweepd::client {

class ReceiveTimeout : public ConnectionLost {
 public:
  using ConnectionLost::ConnectionLost;
};

}  // namespace sweepd::client
