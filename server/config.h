// ServerConfig: how sweepd is set up — from command-line flags and an optional JSON config
// file (flags win over the file, the file over the defaults).
//
// parse_server_config(args): args are argv[1..] (program name excluded). Throws ConfigError
// naming the flag, key or file and the reason (unknown flag, missing value, bad number,
// unreadable or invalid JSON, a --collision other than auto/gpu/cpu, an --http-listen or
// --ws-listen on another listener's port, a --vmc-listen that is not ADDR[:PORT][=MODEL]
// or poses a model another one poses, --viewer-dir without --http-listen, --tls-cert without
// --tls-key or the reverse, --tls-client-ca without them, a token on a plain TCP listener that
// is not loopback without --allow-plaintext, the same for --ws-listen). `--help` sets `show_help`.
// config_usage(): the text `sweepd --help` prints, listing every flag and config key.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "gpu/collision_backend.h"
#include "server/services/vmc/vmc_listen.h"

namespace sweepd::server {

struct ServerConfig {
  std::string listen_address = "127.0.0.1";  // TCP listen address
  int port = 7878;                           // 0: ephemeral (see port_file); -1: no TCP
  std::filesystem::path unix_socket;         // empty: no Unix-socket listener
  std::filesystem::path port_file;           // written (tmp + rename) with the bound TCP port
  // The HTTP side port (/healthz, /readyz, /metrics), from --http-listen ADDR:PORT ([v6]:PORT
  // for IPv6); http_port -1: off, 0: a free port (see http_port_file).
  std::string http_address;
  int http_port = -1;
  std::filesystem::path http_port_file;  // written (tmp + rename) with the bound HTTP port
  // The browser viewer's files, read at start-up and served on the HTTP side port at /viewer
  // (server/http/viewer_files.h); empty: /viewer answers 404.
  std::filesystem::path viewer_dir;
  // The WebSocket listener (--ws-listen ADDR:PORT): the protocol's frames as binary messages,
  // with the TCP listener's auth, limits and TLS (wss when --tls-cert is given); ws_port -1:
  // off, 0: a free port (see ws_port_file). ws_allowed_origins: the browser Origins allowed
  // (server/transport/origin_policy.h); empty: no Origin (not a browser) or this host's.
  std::string ws_address;
  int ws_port = -1;
  std::filesystem::path ws_port_file;
  std::vector<std::string> ws_allowed_origins;
  // The VMC receivers (--vmc-listen ADDR[:PORT][=MODEL], repeatable; server/services/vmc/): each
  // a UDP socket whose VMC pose streams (OSC over UDP) pose one held model, and the stream is
  // named by that model; port 0: a free one (see vmc_port_file, a line per receiver, in order).
  // A receiver without =MODEL poses vmc_model; no two pose one model.
  std::vector<VmcListen> vmc_listens;
  std::filesystem::path vmc_port_file;
  std::string vmc_model = "mannequin";
  std::filesystem::path model_dir;                   // .glb/.gltf files clients may load by name
  std::filesystem::path store_dir = "sweepd-store";  // bound models (.sweepbind) + index
  std::string token;                                 // shared auth token; empty: none asked
  // TLS on the TCP and WebSocket listeners (the Unix socket stays plain): certificate chain and
  // private key (PEM); with tls_client_ca, clients must present a certificate signed by that CA
  // (PEM).
  std::filesystem::path tls_cert;
  std::filesystem::path tls_key;
  std::filesystem::path tls_client_ca;
  // A token on plain TCP off loopback crosses the network in clear: refused at start-up unless
  // this says the network is private (e.g. behind a proxy that terminates TLS).
  bool allow_plaintext = false;
  std::uint32_t max_frame_bytes = 64u << 20;
  std::uint32_t max_models = 16;
  // UploadClip (1.4): clips held in memory, at most this many and this many uploaded bytes (BVH
  // text, glTF files) in all.
  std::uint32_t max_clips = 64;
  std::uint64_t max_clip_bytes = 256ull << 20;
  std::uint32_t max_connections = 64;  // authenticated connections (members)
  std::uint32_t max_poses_in_flight = 8;
  std::uint32_t hello_timeout_ms = 5000;  // a connection silent this long before Hello: closed
  // Strangers (server/transport/stranger_slots.h): connections that have not authenticated yet,
  // at most this many in all and from one address; past either, the oldest is shed. They never
  // count against max_connections.
  std::uint32_t max_strangers = 128;
  std::uint32_t max_strangers_per_address = 32;
  // Wrong tokens (server/transport/auth_backoff.h): an address may fail auth_free_failures
  // times; after each further failure its next token is compared only after auth_backoff_ms,
  // doubling per failure, at most auth_backoff_max_ms.
  std::uint32_t auth_free_failures = 5;
  std::uint32_t auth_backoff_ms = 500;
  std::uint32_t auth_backoff_max_ms = 30000;
  // Hostile clients (protocol/README.md, "Limits"): the largest frame before Hello; a frame
  // begun must be whole within frame_timeout_ms; a connection with no request and no work for
  // idle_timeout_ms (0: never) is closed; a reply not taken by the client within
  // send_timeout_ms, or replies queued past max_send_queue_bytes, cut the connection; after
  // max_frame_errors bad frames it is closed. max_buffered_bytes bounds the frames and replies
  // all connections buffer together (ResourceExhausted past it).
  std::uint32_t max_hello_frame_bytes = 64u << 10;
  std::uint32_t frame_timeout_ms = 60000;
  std::uint32_t idle_timeout_ms = 300000;
  std::uint32_t send_timeout_ms = 30000;
  std::uint64_t max_send_queue_bytes = 256ull << 20;
  std::uint64_t max_buffered_bytes = 1ull << 30;
  // Requests' working memory (server/services/work_budget.h): position maps, contact sheets,
  // poses' reply frames, clip uploads, estimated at intake; all clients together at most
  // work_budget_bytes, one client at most work_budget_client_bytes (ResourceExhausted past
  // either).
  std::uint64_t work_budget_bytes = 2ull << 30;
  std::uint64_t work_budget_client_bytes = 1ull << 30;
  std::uint32_t max_frame_errors = 16;
  std::uint32_t max_model_vertices = 2'000'000;  // uploads above it: MemoryLimit
  int worker_threads = 0;                        // 0: one per core
  int deform_threads = 0;                        // threads one pose is split over; 0: idle cores
  // A worker that finished a job polls for the next one this long before it sleeps
  // (server/transport/fair_work_queue.h); 0: it sleeps at once.
  int worker_spin_us = 0;
  int mannequin_vertices = 20000;  // the default model's size
  int position_maps = 1;           // 1: answer PositionMapRequest on the GPU worker (EGL); 0: off
  // Where folding finds its pairs (gpu/collision_backend.h): auto, gpu or cpu.
  gpu::CollisionChoice collision = gpu::CollisionChoice::kAuto;
  bool show_help = false;
};

class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

ServerConfig parse_server_config(std::span<const std::string_view> args);

// Reads `file` (JSON object, keys as in config_usage; // and /* */ comments allowed) into
// `config`.
void apply_config_file(const std::filesystem::path& file, ServerConfig& config);

const char* config_usage();

}  // namespace sweepd::server
