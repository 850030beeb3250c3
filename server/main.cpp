// sweepd: the deformation daemon. Usage: sweepd --help (server/config.h lists the flags).
#include <malloc.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gpu/collision_backend.h"
#include "io/files/durable_file.h"
#include "server/config.h"
#include "server/http/http_side_port.h"
#include "server/log_event.h"
#include "server/models/model_service.h"
#include "server/services/collision_service.h"
#include "server/services/gpu_thread.h"
#include "server/systemd_notifier.h"
#include "server/transport/server.h"
#include "server/transport/tls_context.h"
#include "server/watchdog_pinger.h"

using namespace sweepd;

namespace {

// How long a /metrics scrape waits for the I/O thread to copy its counters.
constexpr std::chrono::milliseconds kSnapshotTimeout{1000};

// One port a line (several: the VMC receivers', in --vmc-listen's order).
void write_port_file(const std::filesystem::path& file, std::span<const int> ports) {
  std::string text;
  for (const int port : ports) text += std::to_string(port) + "\n";
  io::write_file_durably(file, {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()});
}

void write_port_file(const std::filesystem::path& file, int port) {
  write_port_file(file, std::span<const int>(&port, 1));
}

}  // namespace

int main(int argc, char** argv) {
  // A fixed mmap threshold: buffers of 256 KiB and more (pose replies, frames being read) go
  // back to the system when freed. glibc's default raises the threshold after the first such
  // free, so later ones stayed in its arenas and the daemon's memory grew with its clients.
  mallopt(M_MMAP_THRESHOLD, 256 * 1024);
  server::ServerConfig config;
  try {
    const std::vector<std::string_view> args(argv + 1, argv + argc);
    config = server::parse_server_config(args);
  } catch (const server::ConfigError& error) {
    std::fprintf(stderr, "sweepd: %s\n", error.what());
    return 2;
  }
  if (config.show_help) {
    std::fputs(server::config_usage(), stdout);
    return 0;
  }
  // The collision backend is decided before any work: --collision gpu without a usable EGL
  // context is a configuration error. The GPU thread (EGL) starts here unless it is cpu.
  server::GpuThread gpu;
  const bool probe = config.collision != gpu::CollisionChoice::kCpu;
  const gpu::EglDevice device = probe ? gpu.device() : gpu::EglDevice{};
  gpu::CollisionBackendDecision collision_backend;
  try {
    collision_backend = gpu::choose_collision_backend(config.collision, device);
  } catch (const gpu::CollisionBackendError& error) {
    server::log_event("fatal", {{"reason", error.what()}});
    std::fprintf(stderr, "sweepd: %s\n", error.what());
    return 2;
  }
  server::log_event("collision_backend",
                    {{"backend", gpu::to_string(collision_backend.backend)},
                     {"choice", gpu::to_string(config.collision)},
                     {"device", !probe                   ? "not probed"
                                : device.failure.empty() ? device.renderer
                                                         : "none: " + device.failure},
                     {"software", device.software},
                     {"reason", collision_backend.reason}});
  server::CollisionService collision(gpu, collision_backend);
  // Under systemd (Type=notify, deploy/sweepd.service) each stage is a STATUS= line, READY=1
  // comes when /readyz turns 200 and STOPPING=1 on SIGTERM; without NOTIFY_SOCKET, nothing.
  server::SystemdNotifier systemd;
  try {
    // Certificates that will not load stop the start before any work.
    std::optional<asio::ssl::context> tls;
    if (!config.tls_cert.empty()) tls.emplace(server::server_tls_context(config));
    server::Readiness readiness(
        [&systemd](server::Readiness::Stage stage) { systemd.stage(stage); });
    systemd.stage(readiness.stage());
    server::ModelService models(config);
    // Declared before the side port, which reads it from its own thread: it outlives it.
    std::optional<server::Server> server;
    std::atomic<server::Server*> serving{nullptr};
    // Read before the side port opens: a folder that will not load stops the start.
    std::optional<server::ViewerFiles> viewer;
    if (!config.viewer_dir.empty()) viewer.emplace(config.viewer_dir);
    std::optional<server::HttpSidePort> http;
    if (config.http_port >= 0) {
      // Up before the store is restored: /healthz answers and /readyz says what it waits for.
      http.emplace(
          config.http_address, config.http_port, readiness,
          [&serving, &models]() -> std::optional<server::ServerSnapshot> {
            server::Server* running = serving.load();
            if (running == nullptr) return std::nullopt;
            std::optional<server::ServerSnapshot> snapshot = running->snapshot(kSnapshotTimeout);
            // The store's listing on the side port's thread, not the I/O thread's.
            if (snapshot) snapshot->store_bytes = models.store_bytes();
            return snapshot;
          },
          viewer ? &*viewer : nullptr);
      if (!config.http_port_file.empty()) write_port_file(config.http_port_file, http->port());
    }
    models.restore();
    // With no model directory the procedural mannequin is the default model "mannequin"; it
    // is bound once and kept in the store like any other model.
    readiness.set(server::Readiness::Stage::kBindingDefaultModel);
    models.add_default_model();
    readiness.set(server::Readiness::Stage::kOpeningListeners);
    const auto watchdog_timeout = systemd.watchdog_timeout();
    server::log_event("starting",
                      {{"store_dir", config.store_dir.string()},
                       {"model_dir", config.model_dir.string()},
                       {"auth", config.token.empty() ? "none (any token accepted)" : "token"},
                       {"tls", config.tls_cert.empty() ? "off" : "on"},
                       {"allow_plaintext", config.allow_plaintext},
                       {"max_connections", config.max_connections},
                       {"max_strangers", config.max_strangers},
                       {"max_strangers_per_address", config.max_strangers_per_address},
                       {"max_models", config.max_models},
                       {"max_frame_bytes", config.max_frame_bytes},
                       {"max_poses_in_flight", config.max_poses_in_flight},
                       {"worker_threads", config.worker_threads},
                       {"worker_spin_us", config.worker_spin_us},
                       {"position_maps", config.position_maps != 0},
                       {"systemd_notify", systemd.enabled()},
                       {"watchdog_ms", watchdog_timeout ? watchdog_timeout->count() / 1000 : 0}});
    server.emplace(config, models, readiness, std::move(tls), gpu, collision);
    serving = &*server;
    // WATCHDOG=1 only while the I/O thread answers (a snapshot is a job it runs); declared
    // after `server`, so it stops before the server goes.
    std::optional<server::WatchdogPinger> watchdog;
    if (watchdog_timeout) {
      watchdog.emplace(systemd, *watchdog_timeout, [&server](std::chrono::milliseconds wait) {
        return server->snapshot(wait).has_value();
      });
    }
    const int port = server->open();
    // The WebSocket and VMC ports first: whoever waits for the port file finds them all.
    if (!config.ws_port_file.empty())
      write_port_file(config.ws_port_file, server->websocket_port());
    if (!config.vmc_port_file.empty()) write_port_file(config.vmc_port_file, server->vmc_ports());
    if (!config.port_file.empty()) write_port_file(config.port_file, port);
    std::printf("sweepd listening port=%d\n", port);
    std::fflush(stdout);
    server->run();
  } catch (const std::exception& error) {
    server::log_event("fatal", {{"reason", error.what()}});
    systemd.status(std::string("failed: ") + error.what());
    std::fprintf(stderr, "sweepd: %s\n", error.what());
    return 1;
  }
  return 0;
}
