#include "server/transport/lingering_close.h"

#include <array>
#include <cstdint>
#include <memory>

namespace sweepd::server {
namespace {

class LingeringSocket : public std::enable_shared_from_this<LingeringSocket> {
 public:
  explicit LingeringSocket(asio::generic::stream_protocol::socket socket)
      : socket_(std::move(socket)), deadline_(socket_.get_executor()) {}

  void start() {
    std::error_code ignored;
    socket_.shutdown(asio::socket_base::shutdown_send, ignored);
    deadline_.expires_after(kLingerLimit);
    deadline_.async_wait([self = shared_from_this()](std::error_code error) {
      if (!error) self->close();  // the peer neither closed nor stopped sending
    });
    read_and_drop();
  }

 private:
  void read_and_drop() {
    socket_.async_read_some(asio::buffer(dropped_),
                            [self = shared_from_this()](std::error_code error, std::size_t) {
                              if (error) {  // the peer's end (or a reset, or the deadline)
                                self->close();
                                return;
                              }
                              self->read_and_drop();
                            });
  }

  void close() {
    std::error_code ignored;
    deadline_.cancel();
    socket_.close(ignored);
  }

  asio::generic::stream_protocol::socket socket_;
  asio::steady_timer deadline_;
  std::array<std::uint8_t, 4096> dropped_{};
};

}  // namespace

void close_lingering(asio::generic::stream_protocol::socket socket) {
  if (!socket.is_open()) return;
  std::make_shared<LingeringSocket>(std::move(socket))->start();
}

}  // namespace sweepd::server
