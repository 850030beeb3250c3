#include "server/http/http_side_port.h"

#include <array>
#include <csignal>
#include <stdexcept>

#include "server/http/http_request_head.h"
#include "server/http/metrics_text.h"
#include "server/http/process_stats.h"
#include "server/http/side_port_answers.h"
#include "server/log_event.h"

namespace sweepd::server {

class HttpSidePort::Exchange : public std::enable_shared_from_this<Exchange> {
 public:
  Exchange(HttpSidePort& side_port, asio::ip::tcp::socket socket, std::uint64_t id)
      : side_port_(side_port), socket_(std::move(socket)), deadline_(side_port.io_), id_(id) {}

  void start() {
    arm_deadline(kHeadDeadline, [](Exchange& self) {
      // A wait that expired just as the head became whole may still run: it answers nothing.
      if (!self.reading_head()) return;
      self.answer({408,
                   kPlainText,
                   "the request head was not whole within " +
                       std::to_string(kHeadDeadline.count()) + " ms\n",
                   {}},
                  false);
    });
    read_more();
  }
  bool reading_head() const { return !head_read_ && !closed_; }

  // Writes `answer` and closes; nothing is read after it.
  void answer(const HttpAnswer& answer, bool head_only) {
    if (closed_ || answering_) return;
    head_read_ = answering_ = true;
    arm_deadline(kAnswerDeadline, [](Exchange& self) { self.close(); });
    response_ = http_response_bytes(answer, head_only);
    asio::async_write(socket_, asio::buffer(response_),
                      [self = shared_from_this()](std::error_code, std::size_t) { self->close(); });
  }

  void close() {
    if (closed_) return;
    closed_ = true;
    std::error_code ignored;
    deadline_.cancel();
    socket_.shutdown(asio::ip::tcp::socket::shutdown_both, ignored);
    socket_.close(ignored);
    side_port_.exchanges_.erase(id_);
  }

 private:
  void arm_deadline(std::chrono::milliseconds after, void (*expired)(Exchange&)) {
    deadline_.expires_after(after);
    deadline_.async_wait([self = shared_from_this(), expired](std::error_code error) {
      if (!error && !self->closed_) expired(*self);
    });
  }

  void read_more() {
    socket_.async_read_some(asio::buffer(chunk_),
                            [self = shared_from_this()](std::error_code error, std::size_t n) {
                              if (self->closed_ || self->head_read_) return;
                              if (error) {
                                self->close();
                                return;
                              }
                              self->received_.append(self->chunk_.data(), n);
                              self->read_head();
                            });
  }

  void read_head() {
    const HttpRequestHead head = read_request_head(received_, kMaxRequestHeadBytes);
    switch (head.status) {
      case HttpRequestHead::Status::kIncomplete:
        read_more();
        return;
      case HttpRequestHead::Status::kTooLarge:
        answer({431,
                kPlainText,
                "the request head passed " + std::to_string(kMaxRequestHeadBytes) + " bytes\n",
                {}},
               false);
        return;
      case HttpRequestHead::Status::kBad:
        answer({400, kPlainText, head.problem + "\n", {}}, false);
        return;
      case HttpRequestHead::Status::kComplete:
        break;
    }
    head_read_ = true;
    // The head deadline no longer applies: /metrics may take its second on the other thread.
    arm_deadline(kAnswerDeadline, [](Exchange& self) { self.close(); });
    const bool head_only = head.method == "HEAD";
    if (std::optional<HttpAnswer> now =
            answer_at_once(head, side_port_.readiness_, side_port_.viewer_)) {
      answer(*now, head_only);
      return;
    }
    side_port_.answer_metrics(shared_from_this(), head_only);
  }

  HttpSidePort& side_port_;
  asio::ip::tcp::socket socket_;
  asio::steady_timer deadline_;
  std::uint64_t id_;
  std::array<char, 1024> chunk_{};
  std::string received_;
  std::string response_;
  bool head_read_ = false;
  bool answering_ = false;
  bool closed_ = false;
};

HttpSidePort::HttpSidePort(const std::string& address, int port, const Readiness& readiness,
                           SnapshotSource snapshot, const ViewerFiles* viewer)
    : readiness_(readiness),
      snapshot_(std::move(snapshot)),
      viewer_(viewer),
      acceptor_(io_),
      accept_retry_(io_),
      reading_(kMaxReading, kMaxReadingPerAddress) {
  std::signal(SIGPIPE, SIG_IGN);
  try {
    asio::ip::tcp::resolver resolver(io_);
    const asio::ip::tcp::endpoint endpoint =
        resolver.resolve(address, std::to_string(port))->endpoint();
    acceptor_.open(endpoint.protocol());
    acceptor_.set_option(asio::socket_base::reuse_address(true));
    acceptor_.bind(endpoint);
    acceptor_.listen();
    port_ = acceptor_.local_endpoint().port();
  } catch (const std::exception& error) {
    throw std::runtime_error("cannot listen on HTTP side port " + address + ":" +
                             std::to_string(port) + " (" + error.what() + ")");
  }
  accept_next();
  thread_ = std::thread([this]() { io_.run(); });
  log_event("listening", {{"http_address", address}, {"http_port", port_}});
}

HttpSidePort::~HttpSidePort() {
  io_.stop();
  thread_.join();
  metrics_thread_.join();
}

void HttpSidePort::accept_next() {
  acceptor_.async_accept([this](std::error_code error, asio::ip::tcp::socket socket) {
    if (error == asio::error::operation_aborted) return;
    if (!error) {
      admit(std::move(socket));
      accept_next();
      return;
    }
    // Out of descriptors, say: trying again at once would spin this thread (as the protocol's
    // listeners, server/transport/server.cpp).
    accept_retry_.expires_after(std::chrono::milliseconds(100));
    accept_retry_.async_wait([this](std::error_code) { accept_next(); });
  });
}

void HttpSidePort::admit(asio::ip::tcp::socket socket) {
  std::error_code error;
  const asio::ip::tcp::endpoint peer = socket.remote_endpoint(error);
  if (error) return;  // gone already
  const std::uint64_t id = next_exchange_++;
  auto exchange = std::make_shared<Exchange>(*this, std::move(socket), id);
  exchanges_.emplace(id, exchange);
  reading_.forget([this](std::uint64_t reading) {
    const std::shared_ptr<Exchange> other = find(reading);
    return other != nullptr && other->reading_head();
  });
  for (const StrangerSlots::Shed& shed : reading_.admit(id, peer.address().to_string())) {
    if (const std::shared_ptr<Exchange> slow = find(shed.id)) slow->close();
  }
  exchange->start();
}

std::shared_ptr<HttpSidePort::Exchange> HttpSidePort::find(std::uint64_t id) const {
  const auto found = exchanges_.find(id);
  return found == exchanges_.end() ? nullptr : found->second.lock();
}

void HttpSidePort::answer_metrics(std::shared_ptr<Exchange> exchange, bool head_only) {
  if (metrics_waiting_ >= kMaxMetricsWaiting) {
    exchange->answer(
        {503,
         kPlainText,
         std::to_string(metrics_waiting_) + " /metrics requests are being answered; ask again\n",
         {}},
        head_only);
    return;
  }
  ++metrics_waiting_;
  asio::post(metrics_thread_, [this, exchange = std::move(exchange), head_only]() {
    const std::optional<ServerSnapshot> server = snapshot_();
    HttpAnswer page{
        200,
        kMetricsContentType,
        format_metrics(server ? &*server : nullptr, read_process_stats(), readiness_.stage()),
        {}};
    asio::post(io_, [this, exchange, head_only, page = std::move(page)]() {
      --metrics_waiting_;
      exchange->answer(page, head_only);
    });
  });
}

}  // namespace sweepd::server
