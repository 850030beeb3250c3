#include "server/config.h"

#include <asio/ip/address.hpp>
#include <algorithm>
#include <charconv>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>

namespace sweepd::server {
namespace {

// One setting, under its flag name (--max-frame-bytes) and config key (max_frame_bytes).
struct Setting {
  const char* key;
  std::function<void(ServerConfig&, const std::string& value, const std::string& where)> apply;
};

std::int64_t parse_integer(const std::string& value, const std::string& where, std::int64_t low,
                           std::int64_t high) {
  std::int64_t number = 0;
  const char* end = value.data() + value.size();
  auto [stop, error] = std::from_chars(value.data(), end, number);
  if (error != std::errc() || stop != end) {
    throw ConfigError(where + ": '" + value + "' is not an integer");
  }
  if (number < low || number > high) {
    throw ConfigError(where + ": " + value + " is out of range [" + std::to_string(low) + ", " +
                      std::to_string(high) + "]");
  }
  return number;
}

template <typename Field>
Setting integer_setting(const char* key, Field ServerConfig::*field, std::int64_t low,
                        std::int64_t high) {
  return {key, [field, low, high](ServerConfig& config, const std::string& value,
                                  const std::string& where) {
            config.*field = static_cast<Field>(parse_integer(value, where, low, high));
          }};
}

template <typename Field>
Setting text_setting(const char* key, Field ServerConfig::*field) {
  return {key, [field](ServerConfig& config, const std::string& value, const std::string&) {
            config.*field = Field(value);
          }};
}

// "ADDR:PORT" or "[V6ADDR]:PORT" into `address` and `port`.
Setting address_and_port_setting(const char* key, std::string ServerConfig::*address_field,
                                 int ServerConfig::*port_field) {
  return {key, [address_field, port_field](ServerConfig& config, const std::string& value,
                                           const std::string& where) {
            const std::size_t colon = value.rfind(':');
            if (colon == std::string::npos || colon == 0) {
              throw ConfigError(where + ": '" + value + "' is not ADDR:PORT");
            }
            std::string address = value.substr(0, colon);
            if (address.front() == '[' && address.back() == ']') {
              address = address.substr(1, address.size() - 2);
            }
            config.*port_field =
                static_cast<int>(parse_integer(value.substr(colon + 1), where, 0, 65535));
            config.*address_field = address;
          }};
}

// "ADDR", "ADDR:PORT", "[V6ADDR]" or "[V6ADDR]:PORT" (a bare V6ADDR has no port), then
// "=MODEL" or nothing, into a VmcListen (its port VMC's when none is given).
VmcListen parse_vmc_listen(const std::string& value, const std::string& where) {
  const std::size_t equals = value.find('=');
  const std::string address_and_port = value.substr(0, equals);
  VmcListen listen;
  if (equals != std::string::npos) {
    listen.model = value.substr(equals + 1);
    if (listen.model.empty()) throw ConfigError(where + ": '" + value + "' names no model after '='");
  }
  std::string port;
  listen.address = address_and_port;
  if (!address_and_port.empty() && address_and_port.front() == '[') {
    const std::size_t close = address_and_port.find(']');
    if (close == std::string::npos ||
        (close + 1 < address_and_port.size() && address_and_port[close + 1] != ':'))
      throw ConfigError(where + ": '" + value + "' is not ADDR[:PORT][=MODEL]");
    listen.address = address_and_port.substr(1, close - 1);
    if (close + 1 < address_and_port.size()) port = address_and_port.substr(close + 2);
  } else if (std::count(address_and_port.begin(), address_and_port.end(), ':') == 1) {
    listen.address = address_and_port.substr(0, address_and_port.find(':'));
    port = address_and_port.substr(address_and_port.find(':') + 1);
  }
  if (listen.address.empty()) throw ConfigError(where + ": '" + value + "' names no address");
  if (!port.empty()) listen.port = static_cast<int>(parse_integer(port, where, 0, 65535));
  return listen;
}

// Each --vmc-listen adds a receiver (a comma-separated list adds several: the config file's
// one string).
Setting vmc_listen_setting(const char* key) {
  return {key, [](ServerConfig& config, const std::string& value, const std::string& where) {
            std::size_t start = 0;
            while (start <= value.size()) {
              const std::size_t comma = std::min(value.find(',', start), value.size());
              config.vmc_listens.push_back(
                  parse_vmc_listen(value.substr(start, comma - start), where));
              start = comma + 1;
            }
          }};
}

// A comma-separated list, added to what earlier flags or the file gave.
Setting list_setting(const char* key, std::vector<std::string> ServerConfig::*field) {
  return {key, [field](ServerConfig& config, const std::string& value, const std::string&) {
            std::size_t start = 0;
            while (start <= value.size()) {
              const std::size_t comma = std::min(value.find(',', start), value.size());
              if (comma > start) (config.*field).push_back(value.substr(start, comma - start));
              start = comma + 1;
            }
          }};
}

Setting collision_setting(const char* key) {
  return {key, [](ServerConfig& config, const std::string& value, const std::string& where) {
            const auto choice = gpu::parse_collision_choice(value);
            if (!choice) throw ConfigError(where + ": '" + value + "' is not auto, gpu or cpu");
            config.collision = *choice;
          }};
}

const std::vector<Setting>& settings() {
  static const std::vector<Setting> all = {
      text_setting("listen", &ServerConfig::listen_address),
      integer_setting("port", &ServerConfig::port, -1, 65535),
      text_setting("unix_socket", &ServerConfig::unix_socket),
      text_setting("port_file", &ServerConfig::port_file),
      address_and_port_setting("http_listen", &ServerConfig::http_address,
                               &ServerConfig::http_port),
      text_setting("http_port_file", &ServerConfig::http_port_file),
      text_setting("viewer_dir", &ServerConfig::viewer_dir),
      address_and_port_setting("ws_listen", &ServerConfig::ws_address, &ServerConfig::ws_port),
      text_setting("ws_port_file", &ServerConfig::ws_port_file),
      list_setting("ws_allowed_origin", &ServerConfig::ws_allowed_origins),
      vmc_listen_setting("vmc_listen"),
      text_setting("vmc_port_file", &ServerConfig::vmc_port_file),
      text_setting("vmc_model", &ServerConfig::vmc_model),
      text_setting("model_dir", &ServerConfig::model_dir),
      text_setting("store_dir", &ServerConfig::store_dir),
      text_setting("token", &ServerConfig::token),
      text_setting("tls_cert", &ServerConfig::tls_cert),
      text_setting("tls_key", &ServerConfig::tls_key),
      text_setting("tls_client_ca", &ServerConfig::tls_client_ca),
      integer_setting("allow_plaintext", &ServerConfig::allow_plaintext, 0, 1),
      integer_setting("max_frame_bytes", &ServerConfig::max_frame_bytes, 1024, 1u << 30),
      integer_setting("max_models", &ServerConfig::max_models, 1, 100000),
      integer_setting("max_clips", &ServerConfig::max_clips, 1, 100000),
      integer_setting("max_clip_bytes", &ServerConfig::max_clip_bytes, 0, 1ll << 40),
      integer_setting("max_connections", &ServerConfig::max_connections, 1, 100000),
      integer_setting("max_poses_in_flight", &ServerConfig::max_poses_in_flight, 1, 4096),
      integer_setting("hello_timeout_ms", &ServerConfig::hello_timeout_ms, 1, 3'600'000),
      integer_setting("max_strangers", &ServerConfig::max_strangers, 1, 100000),
      integer_setting("max_strangers_per_address", &ServerConfig::max_strangers_per_address, 1,
                      100000),
      integer_setting("auth_free_failures", &ServerConfig::auth_free_failures, 0, 1'000'000),
      integer_setting("auth_backoff_ms", &ServerConfig::auth_backoff_ms, 1, 3'600'000),
      integer_setting("auth_backoff_max_ms", &ServerConfig::auth_backoff_max_ms, 1, 86'400'000),
      integer_setting("max_hello_frame_bytes", &ServerConfig::max_hello_frame_bytes, 256, 1u << 30),
      integer_setting("frame_timeout_ms", &ServerConfig::frame_timeout_ms, 1, 3'600'000),
      integer_setting("idle_timeout_ms", &ServerConfig::idle_timeout_ms, 0, 86'400'000),
      integer_setting("send_timeout_ms", &ServerConfig::send_timeout_ms, 1, 3'600'000),
      integer_setting("max_send_queue_bytes", &ServerConfig::max_send_queue_bytes, 1 << 20,
                      1ll << 40),
      integer_setting("max_buffered_bytes", &ServerConfig::max_buffered_bytes, 1 << 20, 1ll << 40),
      integer_setting("work_budget_bytes", &ServerConfig::work_budget_bytes, 1 << 20, 1ll << 40),
      integer_setting("work_budget_client_bytes", &ServerConfig::work_budget_client_bytes, 1 << 20,
                      1ll << 40),
      integer_setting("max_frame_errors", &ServerConfig::max_frame_errors, 1, 1'000'000),
      integer_setting("max_model_vertices", &ServerConfig::max_model_vertices, 1, 100'000'000),
      integer_setting("worker_threads", &ServerConfig::worker_threads, 0, 1024),
      integer_setting("deform_threads", &ServerConfig::deform_threads, 0, 1024),
      integer_setting("worker_spin_us", &ServerConfig::worker_spin_us, 0, 100'000),
      integer_setting("mannequin_vertices", &ServerConfig::mannequin_vertices, 1000, 500000),
      integer_setting("position_maps", &ServerConfig::position_maps, 0, 1),
      collision_setting("collision"),
  };
  return all;
}

const Setting* find_setting(const std::string& key) {
  for (const Setting& setting : settings()) {
    if (key == setting.key) return &setting;
  }
  return nullptr;
}

std::string flag_to_key(std::string_view flag) {
  std::string key(flag.substr(2));
  for (char& c : key) {
    if (c == '-') c = '_';
  }
  return key;
}

bool is_loopback(const std::string& address) {
  std::error_code error;
  const asio::ip::address parsed = asio::ip::make_address(address, error);
  return !error && parsed.is_loopback();
}

// The flags that only make sense together, and the token that must not cross a network in
// clear.
void check_transport_security(const ServerConfig& config) {
  if (config.tls_cert.empty() != config.tls_key.empty()) {
    throw ConfigError(config.tls_cert.empty() ? "--tls-key: needs --tls-cert (the certificate)"
                                              : "--tls-cert: needs --tls-key (its private key)");
  }
  const bool tls = !config.tls_cert.empty();
  if (!config.tls_client_ca.empty() && !tls) {
    throw ConfigError(
        "--tls-client-ca: needs --tls-cert and --tls-key (client certificates are "
        "checked in the TLS handshake)");
  }
  const auto check_plain = [&](bool listening, const std::string& address, const char* what,
                               const char* loopback_flag) {
    if (!config.token.empty() && listening && !tls && !config.allow_plaintext &&
        !is_loopback(address)) {
      throw ConfigError(std::string("--token: ") + what + " on " + address +
                        " would send the token across the network in clear; give --tls-cert "
                        "FILE --tls-key FILE, or " +
                        loopback_flag +
                        ", or --allow-plaintext where the network is private (e.g. behind a "
                        "proxy that terminates TLS)");
    }
  };
  check_plain(config.port >= 0, config.listen_address, "plain TCP", "--listen 127.0.0.1");
  check_plain(config.ws_port >= 0, config.ws_address, "plain WebSocket",
              "--ws-listen 127.0.0.1:PORT");
}

// Every receiver without =MODEL poses --vmc-model's; a stream is named by its model, so no two
// receivers pose one model, and no two bind one port.
void name_vmc_models(ServerConfig& config) {
  const auto named = [](const VmcListen& listen) {
    const bool v6 = listen.address.find(':') != std::string::npos;
    return (v6 ? "[" + listen.address + "]" : listen.address) + ":" + std::to_string(listen.port) +
           "=" + listen.model;
  };
  for (std::size_t i = 0; i < config.vmc_listens.size(); ++i) {
    VmcListen& listen = config.vmc_listens[i];
    if (listen.model.empty()) listen.model = config.vmc_model;
    for (std::size_t earlier = 0; earlier < i; ++earlier) {
      const VmcListen& other = config.vmc_listens[earlier];
      if (other.model == listen.model) {
        throw ConfigError("--vmc-listen " + named(listen) + ": the model '" + listen.model +
                          "' is posed by --vmc-listen " + named(other) +
                          " already; a stream is named by its model, one receiver each");
      }
      if (listen.port != 0 && other.port == listen.port && other.address == listen.address) {
        throw ConfigError("--vmc-listen " + named(listen) + ": the same address and port as " +
                          "--vmc-listen " + named(other) + "; each receiver needs its own port");
      }
    }
  }
}

std::string read_token_file(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw ConfigError("--token-file " + file.string() + ": cannot read the file");
  std::string token;
  std::getline(in, token);
  return token;
}

}  // namespace

void apply_config_file(const std::filesystem::path& file, ServerConfig& config) {
  std::ifstream in(file);
  if (!in) throw ConfigError("config file " + file.string() + ": cannot read the file");
  nlohmann::json json;
  try {
    // Comments (// and /* */) are allowed: deploy/sweepd.conf explains its keys.
    json = nlohmann::json::parse(in, /*cb=*/nullptr, /*allow_exceptions=*/true,
                                 /*ignore_comments=*/true);
  } catch (const nlohmann::json::exception& error) {
    throw ConfigError("config file " + file.string() + ": not valid JSON (" + error.what() + ")");
  }
  if (!json.is_object()) {
    throw ConfigError("config file " + file.string() + ": the top level must be an object");
  }
  for (const auto& [key, value] : json.items()) {
    const std::string where = "config file " + file.string() + ", key '" + key + "'";
    const Setting* setting = find_setting(key);
    if (setting == nullptr) throw ConfigError(where + ": unknown key");
    if (value.is_string()) {
      setting->apply(config, value.get<std::string>(), where);
    } else if (value.is_number_integer()) {
      setting->apply(config, std::to_string(value.get<std::int64_t>()), where);
    } else if (value.is_boolean()) {
      setting->apply(config, value.get<bool>() ? "1" : "0", where);
    } else {
      throw ConfigError(where + ": expected a string, an integer or a boolean");
    }
  }
}

ServerConfig parse_server_config(std::span<const std::string_view> args) {
  // The config file comes first so that flags override it wherever they stand.
  ServerConfig config;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--config") {
      if (i + 1 >= args.size()) throw ConfigError("--config: missing value");
      apply_config_file(std::filesystem::path(args[i + 1]), config);
    }
  }
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string_view flag = args[i];
    if (flag == "--help" || flag == "-h") {
      config.show_help = true;
      continue;
    }
    if (flag == "--allow-plaintext") {  // a switch: no value
      config.allow_plaintext = true;
      continue;
    }
    if (!flag.starts_with("--")) {
      throw ConfigError("'" + std::string(flag) + "': not a flag (see --help)");
    }
    if (i + 1 >= args.size()) throw ConfigError(std::string(flag) + ": missing value");
    const std::string value(args[++i]);
    if (flag == "--config") continue;
    if (flag == "--token-file") {
      config.token = read_token_file(value);
      continue;
    }
    const Setting* setting = find_setting(flag_to_key(flag));
    if (setting == nullptr) throw ConfigError(std::string(flag) + ": unknown flag (see --help)");
    setting->apply(config, value, std::string(flag));
  }
  if (config.http_port > 0 && config.http_port == config.port) {
    throw ConfigError("--http-listen: port " + std::to_string(config.http_port) +
                      " is the protocol port (--port); the HTTP side port needs its own");
  }
  if (!config.viewer_dir.empty() && config.http_port < 0) {
    throw ConfigError(
        "--viewer-dir: needs --http-listen (the viewer is served on the HTTP side port)");
  }
  if (config.ws_port > 0 && (config.ws_port == config.port || config.ws_port == config.http_port)) {
    throw ConfigError("--ws-listen: port " + std::to_string(config.ws_port) +
                      " is already the protocol or HTTP side port; the WebSocket listener needs "
                      "its own");
  }
  check_transport_security(config);
  name_vmc_models(config);
  return config;
}

const char* config_usage() {
  return R"(usage: sweepd [flags]
Flags (each also a key of the JSON config file, with '_' for '-'):
  --config FILE             JSON object of the keys below (// and /* */ comments allowed);
                            flags override it
  --listen ADDR             TCP listen address (default 127.0.0.1)
  --port N                  TCP port; 0 picks a free one, -1 disables TCP (default 7878)
  --unix-socket PATH        also listen on a Unix socket at PATH
  --port-file FILE          write the bound TCP port to FILE once listening
  --http-listen ADDR:PORT   HTTP side port for /healthz, /readyz and /metrics (Prometheus);
                            [V6ADDR]:PORT for IPv6, PORT 0 picks a free one; never the
                            protocol port (default: off)
  --http-port-file FILE     write the bound HTTP side port to FILE once listening
  --viewer-dir DIR          serve the browser viewer (the build's client_examples/web/viewer)
                            at /viewer on the HTTP side port; its files are read once, at
                            start-up (default: off)
  --ws-listen ADDR:PORT     WebSocket listener: the protocol's frames, one per binary message,
                            with the TCP listener's token, limits and TLS (wss with
                            --tls-cert); [V6ADDR]:PORT for IPv6, PORT 0 picks a free one
                            (default: off)
  --ws-port-file FILE       write the bound WebSocket port to FILE once listening
  --ws-allowed-origin LIST  browser Origins (scheme://host[:port], comma-separated, or *) that
                            may connect; repeatable. Default: requests without Origin (not a
                            browser) and pages served by the host the request names
  --vmc-listen ADDR[:PORT][=MODEL]
                            receive VMC pose streams (OSC 1.0 over UDP, protocol.vmc.info):
                            their bones pose the held model MODEL (default: --vmc-model's),
                            the stream's name, whose posed meshes go to SubscribeStream's
                            subscribers; repeatable, a receiver (a port) per model, or a
                            comma-separated list; PORT 0 picks a free one ([V6ADDR]:PORT for
                            IPv6; default port 39539; default: off)
  --vmc-port-file FILE      write the bound VMC ports to FILE once listening, a line each,
                            in --vmc-listen's order
  --vmc-model NAME          the model a --vmc-listen without =MODEL poses (default mannequin)
  --model-dir DIR           .glb/.gltf files clients may load by name
  --store-dir DIR           where bound models are kept (default ./sweepd-store)
  --token TOKEN             shared token clients must send in Hello (default: none)
  --token-file FILE         read the token from the first line of FILE (not a config key)
  --tls-cert FILE           TLS on the TCP and WebSocket listeners: certificate chain (PEM;
                            needs --tls-key); TLS 1.2 at least, 1.3 preferred; the Unix
                            socket stays plain
  --tls-key FILE            the certificate's private key (PEM)
  --tls-client-ca FILE      require a client certificate signed by this CA (PEM)
  --allow-plaintext         allow --token on plain TCP or WebSocket off loopback (a private network, e.g.
                            behind a proxy that terminates TLS); without it that is refused
                            at start-up (config key: allow_plaintext true)
  --max-frame-bytes N       largest accepted frame (default 67108864)
  --max-models N            most models held (default 16)
  --max-clips N             most motion clips held, in memory (UploadClip; default 64)
  --max-clip-bytes N        uploaded bytes (BVH text, glTF files) of all clips held (default 268435456)
  --max-connections N       most authenticated connections at once; connections that have
                            not said Hello yet count apart (default 64)
  --max-poses-in-flight N   queued poses per connection before backpressure (default 8)
  --hello-timeout-ms N      close connections that send no Hello in time, the TLS handshake
                            included (default 5000)
  --max-strangers N         most connections that have not authenticated yet; past it the
                            oldest of the address holding most is closed (default 128)
  --max-strangers-per-address N
                            the same from one peer address; past it that address's oldest
                            is closed (default 32)
  --auth-free-failures N    wrong tokens an address may send before it must wait (default 5)
  --auth-backoff-ms N       after each further wrong token, no token of that address is
                            compared for N ms, doubling per failure (default 500)
  --auth-backoff-max-ms N   the longest such wait (default 30000)
  --max-hello-frame-bytes N largest frame before Hello; larger is fatal (default 65536)
  --frame-timeout-ms N      a frame begun must be whole within N ms, else the connection is
                            closed (default 60000)
  --idle-timeout-ms N       close a connection with no request and no work for N ms;
                            0 = never (default 300000)
  --send-timeout-ms N       cut a connection whose client takes no reply bytes for N ms
                            (default 30000)
  --max-send-queue-bytes N  cut a connection whose unread replies pass N bytes
                            (default 268435456)
  --max-buffered-bytes N    frames and replies all connections may buffer together; a frame
                            past it is refused with ResourceExhausted (default 1073741824)
  --work-budget-bytes N     working memory (render targets, read-back, encoding, sheets,
                            decoded clips) all requests may hold together; a request that
                            does not fit now is refused with ResourceExhausted (default 2147483648)
  --work-budget-client-bytes N
                            the same for one client's requests (default 1073741824)
  --max-frame-errors N      close a connection after N bad frames (default 16)
  --max-model-vertices N    largest model accepted for loading (default 2000000)
  --worker-threads N        deformation workers; 0 = one per core (default 0)
  --deform-threads N        threads one pose is split over; 0 = one, plus the idle workers'
                            cores for a pose of 40,000 vertices or more (default 0)
  --worker-spin-us N        a worker that finished a job polls N microseconds for the next
                            before it sleeps, sparing a client that sends one pose at a time
                            a sleeping worker's wake-up (0.03 ms a pose on a 2-core VM), at
                            the cost of the core it polls on; 0 = sleep at once (default 0)
  --mannequin-vertices N    size of the default "mannequin" model (default 20000)
  --position-maps 0|1       render PositionMapRequest with EGL (GPU or llvmpipe) (default 1)
  --collision auto|gpu|cpu  where folding finds intersecting triangle pairs: gpu = compute
                            jobs on the GPU thread (the one that renders position maps), cpu =
                            the CPU reference (the same pairs), auto = gpu on a hardware EGL
                            device, cpu on llvmpipe (software) or without EGL; gpu without a
                            usable EGL context is a start-up error (default auto)
Signals: SIGTERM/SIGINT finish in-flight work, send Bye, and exit 0.
Logs: one JSON object per line on stderr.
)";
}

}  // namespace sweepd::server
