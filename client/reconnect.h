// reconnect: a new connection to a server whose last connection was lost
// (client/connection_lost.h) — a daemon that restarted, or HAProxy that sends the client to
// another replica — made and set up by the caller's `set_up` (Hello, the model with
// client::ModelSource, the clip), for a client that then asks again for what was not answered.
//
//   std::unique_ptr<Connection> connection = reconnect(address, tls, [&](Connection& c) {
//     c.hello(token, "my client");
//     model_id = source.load(c).model_id();   // UnknownModel there: uploaded again
//   });
//
// Tried kReconnectTries times: at once, then after pauses of 0.2, 0.4, ... 6.4 s (12.6 s in
// all: long enough for a daemon to restart on a loaded host, short enough to give up on one
// that is gone). Throws the last try's ConnectionLost; anything else `set_up` throws (a
// ServerError: the server refused) is thrown at once.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "client/client_tls.h"
#include "client/connection.h"

namespace sweepd::client {

inline constexpr int kReconnectTries = 7;

std::unique_ptr<Connection> reconnect(const std::string& address, const ClientTls& tls,
                                      const std::function<void(Connection&)>& set_up);

}  // namespace sweepd::client
