// ConnectionLost: the connection to sweepd could not be made, or broke — the server closed it
// or died, a send or receive failed — as opposed to an answer the server gave (ServerError)
// or a mistake of the caller's. A client may connect again (a daemon that restarts, HAProxy
// moving to another replica) and ask again: client/reconnect.h.
#pragma once

#include <stdexcept>

namespace sweepd::client {

class ConnectionLost : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace sweepd::client
