// HttpSidePort: sweepd's HTTP side port (--http-listen), apart from the protocol port, for
// operators' tools: GET /healthz (200 while the process runs), GET /readyz (200 only while
// `readiness` is accepting; 503 naming the stage otherwise: restoring the store, binding the
// default model, opening the listeners, draining after SIGTERM) and GET /metrics (the
// Prometheus text page of format_metrics) and GET /viewer, /viewer/ and /viewer/NAME (the
// browser viewer: index.html, or the file NAME of `viewer`, from memory; a 404 saying why when
// there is no such file, or no viewer because sweepd has no --viewer-dir). Anything else: 404.
//
// Served by cpp-httplib (Debian's libcpp-httplib-dev) on threads of its own — one acceptor
// and two request threads — so it never runs on the protocol's I/O thread; /metrics asks
// `snapshot` for the server's counters (Server::snapshot: copied on the I/O thread, or
// nullopt). Binds in the constructor (throws std::runtime_error naming the address), serves
// until destroyed. SIGPIPE is ignored process-wide: the library writes without
// MSG_NOSIGNAL, and a scraper that hangs up must not kill the daemon.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "server/http/viewer_files.h"
#include "server/readiness.h"
#include "server/transport/server_snapshot.h"

namespace httplib {
class Server;
}

namespace sweepd::server {

class HttpSidePort {
 public:
  using SnapshotSource = std::function<std::optional<ServerSnapshot>()>;

  // port 0: a free one (see port()). `viewer`: the files served under /viewer (nullptr:
  // none); it must outlive this.
  HttpSidePort(const std::string& address, int port, const Readiness& readiness,
               SnapshotSource snapshot, const ViewerFiles* viewer = nullptr);
  ~HttpSidePort();
  HttpSidePort(const HttpSidePort&) = delete;
  HttpSidePort& operator=(const HttpSidePort&) = delete;

  int port() const { return port_; }

 private:
  const Readiness& readiness_;
  SnapshotSource snapshot_;
  const ViewerFiles* viewer_;
  std::unique_ptr<httplib::Server> http_;
  int port_ = 0;
  std::thread thread_;
};

}  // namespace sweepd::server
