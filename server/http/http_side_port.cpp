#include "server/http/http_side_port.h"

#include <httplib.h>

#include <chrono>
#include <csignal>
#include <stdexcept>

#include "server/handlers/client_string_limits.h"
#include "server/http/metrics_text.h"
#include "server/http/process_stats.h"
#include "server/log_event.h"

namespace sweepd::server {
namespace {

// Two request threads: a scrape and a probe at once; more clients wait their turn.
constexpr std::size_t kRequestThreads = 2;
// A client that sends nothing for this long is dropped: it holds one of the two threads.
constexpr int kClientTimeoutSeconds = 5;

}  // namespace

HttpSidePort::HttpSidePort(const std::string& address, int port, const Readiness& readiness,
                           SnapshotSource snapshot, const ViewerFiles* viewer)
    : readiness_(readiness),
      snapshot_(std::move(snapshot)),
      viewer_(viewer),
      http_(std::make_unique<httplib::Server>()) {
  std::signal(SIGPIPE, SIG_IGN);
  http_->new_task_queue = [] { return new httplib::ThreadPool(kRequestThreads); };
  http_->set_read_timeout(kClientTimeoutSeconds);
  http_->set_write_timeout(kClientTimeoutSeconds);
  http_->set_keep_alive_timeout(kClientTimeoutSeconds);
  http_->Get("/healthz", [](const httplib::Request&, httplib::Response& response) {
    response.set_content("ok\n", "text/plain; charset=utf-8");
  });
  http_->Get("/readyz", [this](const httplib::Request&, httplib::Response& response) {
    const Readiness::Stage stage = readiness_.stage();
    response.status = stage == Readiness::Stage::kAccepting ? 200 : 503;
    response.set_content(std::string(Readiness::describe(stage)) + "\n",
                         "text/plain; charset=utf-8");
  });
  http_->Get("/metrics", [this](const httplib::Request&, httplib::Response& response) {
    const std::optional<ServerSnapshot> server = snapshot_();
    response.set_content(
        format_metrics(server ? &*server : nullptr, read_process_stats(), readiness_.stage()),
        kMetricsContentType);
  });
  // The name is looked up among the files read at start-up; it never reaches the file system.
  http_->Get(R"(/viewer(?:/([^/]*))?)", [this](const httplib::Request& request,
                                               httplib::Response& response) {
    const std::string name =
        request.matches[1].length() > 0 ? request.matches[1].str() : std::string("index.html");
    // The name is echoed below: a name longer than any viewer file's is refused unechoed.
    if (name.size() > kMaxNameBytes) {
      response.status = 414;
      response.set_content("the viewer file name has " + std::to_string(name.size()) +
                               " bytes; the limit is " + std::to_string(kMaxNameBytes) + " bytes\n",
                           "text/plain; charset=utf-8");
      return;
    }
    const ViewerFile* file = viewer_ != nullptr ? viewer_->find(name) : nullptr;
    if (file == nullptr) {
      response.status = 404;
      response.set_content(viewer_ == nullptr
                               ? "no viewer here: sweepd serves /viewer when started with "
                                 "--viewer-dir DIR (the build's client_examples/web/viewer)\n"
                               : "no file '" + name + "' in the viewer\n",
                           "text/plain; charset=utf-8");
      return;
    }
    response.set_header("Cache-Control", "no-cache");
    response.set_header("X-Content-Type-Options", "nosniff");
    response.set_content(file->bytes, file->content_type);
  });
  const bool bound = port == 0 ? (port_ = http_->bind_to_any_port(address)) > 0
                               : http_->bind_to_port(address, port);
  if (!bound) {
    throw std::runtime_error("cannot listen on HTTP side port " + address + ":" +
                             std::to_string(port));
  }
  if (port != 0) port_ = port;
  thread_ = std::thread([this]() { http_->listen_after_bind(); });
  // stop() before the loop runs would be lost: wait until it does.
  while (!http_->is_running()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  log_event("listening", {{"http_address", address}, {"http_port", port_}});
}

HttpSidePort::~HttpSidePort() {
  http_->stop();
  thread_.join();
}

}  // namespace sweepd::server
