// close_lingering(socket): the last step of a connection's close. Closing a socket whose
// receive buffer holds bytes the server never read makes the kernel send RST and drop what
// it had not yet sent: a client that pipelined frames past a fatal error (16 bad frames, a
// wrong token) would lose that Error, the Bye or the WebSocket close frame. So, as HTTP
// servers do (nginx's lingering_close), the socket's sending side is shut (the peer reads
// everything sent, then the end), what the peer still sends is read and dropped until it
// closes too, and the socket is closed then, or after kLingerLimit at the latest.
#pragma once

#include <asio.hpp>
#include <chrono>

namespace sweepd::server {

inline constexpr std::chrono::milliseconds kLingerLimit{2000};

// Takes the socket; no operation may be outstanding on it (cancel them first).
void close_lingering(asio::generic::stream_protocol::socket socket);

}  // namespace sweepd::server
