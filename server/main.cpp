// sweepd: the deformation daemon. Usage: sweepd --help (server/config.h lists the flags).
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "deform/binding/bind.h"
#include "deform/rig/rig_map.h"
#include "io/durable_file.h"
#include "mannequin/mannequin.h"
#include "server/config.h"
#include "server/log_event.h"
#include "server/model_registry.h"
#include "server/server.h"

namespace {

using namespace sweepd;

// With no model directory the procedural mannequin is the default model "mannequin"; it is
// bound once and kept in the store like any other model.
void ensure_default_model(const server::ServerConfig& config, server::ModelRegistry& registry) {
  if (!config.model_dir.empty() || registry.find(std::string_view("mannequin"))) return;
  const auto started = std::chrono::steady_clock::now();
  deform::Model model = mannequin::make_mannequin({.target_vertices = config.mannequin_vertices});
  const deform::RigMap rig = deform::detect_rig_map(model.skeleton);
  deform::BoundModel bound = deform::bind(model, rig);
  const auto bind_time = std::chrono::duration_cast<std::chrono::nanoseconds>(
      std::chrono::steady_clock::now() - started);
  const server::ModelHandle added =
      registry.add("mannequin", std::move(bound), static_cast<std::uint64_t>(bind_time.count()));
  server::log_event("model_loaded", {{"model", added->id},
                                     {"name", added->name},
                                     {"vertices", added->bound.model.vertex_count()},
                                     {"bind_time_ns", added->bind_time_ns}});
}

}  // namespace

int main(int argc, char** argv) {
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
  try {
    server::ModelRegistry registry(
        config.store_dir, config.model_dir,
        {.max_models = config.max_models, .max_model_vertices = config.max_model_vertices});
    for (const std::string& problem : registry.restore()) {
      server::log_event("restore_problem", {{"reason", problem}});
    }
    for (const server::ModelHandle& model : registry.models()) {
      server::log_event("model_restored", {{"model", model->id},
                                           {"name", model->name},
                                           {"vertices", model->bound.model.vertex_count()}});
    }
    ensure_default_model(config, registry);
    server::log_event("starting",
                      {{"store_dir", config.store_dir.string()},
                       {"model_dir", config.model_dir.string()},
                       {"auth", config.token.empty() ? "none (any token accepted)" : "token"},
                       {"max_connections", config.max_connections},
                       {"max_models", config.max_models},
                       {"max_frame_bytes", config.max_frame_bytes},
                       {"max_poses_in_flight", config.max_poses_in_flight},
                       {"worker_threads", config.worker_threads},
                       {"position_maps", config.position_maps != 0}});
    server::Server server(config, registry);
    const int port = server.open();
    if (!config.port_file.empty()) {
      const std::string text = std::to_string(port) + "\n";
      io::write_file_durably(config.port_file,
                             {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()});
    }
    std::printf("sweepd listening port=%d\n", port);
    std::fflush(stdout);
    server.run();
  } catch (const std::exception& error) {
    server::log_event("fatal", {{"reason", error.what()}});
    std::fprintf(stderr, "sweepd: %s\n", error.what());
    return 1;
  }
  return 0;
}
