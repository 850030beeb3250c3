#include "server/http/metrics_text.h"

#include <cstdio>
#include <string_view>

namespace sweepd::server {
namespace {

namespace pb = sweepd::protocol;

// A label value with \, " and newline escaped as the exposition format asks.
std::string escaped(std::string_view value) {
  std::string out;
  for (const char c : value) {
    if (c == '\\') {
      out += "\\\\";
    } else if (c == '"') {
      out += "\\\"";
    } else if (c == '\n') {
      out += "\\n";
    } else {
      out += c;
    }
  }
  return out;
}

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.17g", value);
  return text;
}

class Page {
 public:
  void header(const char* name, const char* type, const char* help) {
    text_ += std::string("# HELP ") + name + " " + help + "\n# TYPE " + name + " " + type + "\n";
  }
  void sample(const std::string& name, const std::string& labels, const std::string& value) {
    text_ += name;
    if (!labels.empty()) text_ += "{" + labels + "}";
    text_ += " " + value + "\n";
  }
  void single(const char* name, const char* type, const char* help, std::uint64_t value) {
    header(name, type, help);
    sample(name, "", std::to_string(value));
  }
  void single(const char* name, const char* type, const char* help, double value) {
    header(name, type, help);
    sample(name, "", number(value));
  }
  void histogram(const char* name, const char* help, const LatencyHistogram& histogram) {
    header(name, "histogram", help);
    std::uint64_t cumulative = 0;
    for (std::size_t b = 0; b < kLatencyBuckets; ++b) {
      cumulative += histogram.bucket_counts()[b];
      char bound[32];
      std::snprintf(bound, sizeof(bound), "%g", kLatencyBucketSeconds[b]);
      sample(std::string(name) + "_bucket", std::string("le=\"") + bound + "\"",
             std::to_string(cumulative));
    }
    sample(std::string(name) + "_bucket", "le=\"+Inf\"", std::to_string(histogram.count()));
    sample(std::string(name) + "_sum", "", number(histogram.sum_seconds()));
    sample(std::string(name) + "_count", "", std::to_string(histogram.count()));
  }
  // A counter with one sample per model, labelled by its name and id.
  void per_model(const char* name, const char* help, const std::vector<ModelSnapshot>& models,
                 std::uint64_t ModelSnapshot::*field) {
    header(name, "counter", help);
    for (const ModelSnapshot& model : models) {
      sample(name, "model=\"" + escaped(model.name) + "\",id=\"" + std::to_string(model.id) + "\"",
             std::to_string(model.*field));
    }
  }
  std::string take() { return std::move(text_); }

 private:
  std::string text_;
};

// The VMC receivers' (--vmc-listen; server/services/vmc/vmc_receivers.h), only when they run: a
// sample per stream, labelled by its name (its model's).
void add_vmc(Page& page, const std::vector<VmcSnapshot>& streams) {
  const auto per_stream = [&](const char* name, const char* type, const char* help,
                              std::uint64_t (*value)(const VmcSnapshot&)) {
    page.header(name, type, help);
    for (const VmcSnapshot& stream : streams)
      page.sample(name, "stream=\"" + escaped(stream.stream) + "\"",
                  std::to_string(value(stream)));
  };
  per_stream("sweepd_vmc_packets_total", "counter", "VMC datagrams received (OSC packets).",
             [](const VmcSnapshot& s) { return s.counters.packets; });
  per_stream("sweepd_vmc_bundles_total", "counter", "OSC bundles read, nested ones included.",
             [](const VmcSnapshot& s) { return s.counters.bundles; });
  per_stream("sweepd_vmc_messages_total", "counter", "OSC messages read from VMC packets.",
             [](const VmcSnapshot& s) { return s.counters.messages; });
  per_stream("sweepd_vmc_bones_total", "counter", "/VMC/Ext/Bone/Pos messages applied to the stream.",
             [](const VmcSnapshot& s) { return s.counters.bones; });
  per_stream("sweepd_vmc_frames_total", "counter",
             "Frames ended (a bundle, /VMC/Ext/OK or /VMC/Ext/T); each poses the stream's model.",
             [](const VmcSnapshot& s) { return s.counters.frames; });
  per_stream("sweepd_vmc_frames_without_model_total", "counter",
             "Frames ended while the stream's model was not held.",
             [](const VmcSnapshot& s) { return s.counters.frames_without_model; });
  page.header("sweepd_vmc_dropped_total", "counter",
              "VMC input dropped: whole packets that are not OSC 1.0 (torn, short, fuzzed), and "
              "messages of a VMC address with wrong type tags or values.");
  for (const VmcSnapshot& stream : streams) {
    const std::string label = "stream=\"" + escaped(stream.stream) + "\",what=";
    page.sample("sweepd_vmc_dropped_total", label + "\"packet\"",
                std::to_string(stream.counters.dropped_packets));
    page.sample("sweepd_vmc_dropped_total", label + "\"message\"",
                std::to_string(stream.counters.dropped_messages));
  }
  per_stream("sweepd_vmc_ignored_messages_total", "counter",
             "Messages of addresses the receiver does not read (blend shapes, unknown ones).",
             [](const VmcSnapshot& s) { return s.counters.ignored_messages; });
  per_stream("sweepd_vmc_senders", "gauge",
             "Addresses the stream's VMC packets came from in the last 10 seconds.",
             [](const VmcSnapshot& s) { return static_cast<std::uint64_t>(s.senders); });
  per_stream("sweepd_vmc_subscribers", "gauge", "Subscriptions to the stream (SubscribeStream).",
             [](const VmcSnapshot& s) { return static_cast<std::uint64_t>(s.subscribers); });
}

void add_server(Page& page, const ServerSnapshot& server) {
  const TrafficCounters& traffic = server.traffic;
  page.header("sweepd_requests_total", "counter",
              "Messages received from clients, by message type (unknown: a type newer than "
              "this server).");
  for (std::size_t t = 0; t < kBodyTypes; ++t) {
    const char* type = t == 0 ? "unknown" : pb::EnumNameBody(static_cast<pb::Body>(t));
    page.sample("sweepd_requests_total", std::string("type=\"") + type + "\"",
                std::to_string(traffic.requests[t]));
  }
  page.header("sweepd_errors_total", "counter", "Error replies sent, by error code.");
  for (std::size_t c = 0; c < kErrorCodes; ++c) {
    page.sample(
        "sweepd_errors_total",
        std::string("code=\"") + pb::EnumNameErrorCode(static_cast<pb::ErrorCode>(c)) + "\"",
        std::to_string(traffic.errors[c]));
  }
  page.histogram("sweepd_pose_latency_seconds",
                 "Pose latency, frame read to reply queued (deformation included).",
                 traffic.pose_latency);
  page.histogram("sweepd_position_map_latency_seconds",
                 "PositionMapRequest latency, frame read to reply queued (render included).",
                 traffic.position_map_latency);
  const ConnectionTotals& all = server.all_connections;
  page.single("sweepd_poses_received_total", "counter", "Poses and position-map requests received.",
              all.poses_received);
  page.single("sweepd_poses_answered_total", "counter",
              "Poses and position maps answered with their reply.", all.poses_answered);
  page.single("sweepd_poses_dropped_total", "counter",
              "Poses replaced by a newer one before they ran (LatestWins delivery).",
              all.poses_dropped);
  page.single("sweepd_received_bytes_total", "counter", "Bytes read from client sockets.",
              all.bytes_in);
  page.single("sweepd_sent_bytes_total", "counter", "Bytes written to client sockets.",
              all.bytes_out);
  page.single("sweepd_connections_accepted_total", "counter",
              "Connections accepted since start (including those shed or refused at Hello).",
              server.connections_accepted);
  page.single("sweepd_connections_open", "gauge", "Client connections open now.",
              server.connections_open);
  page.single("sweepd_websocket_connections_accepted_total", "counter",
              "Of the connections accepted, those on the WebSocket listener (--ws-listen).",
              server.websocket_connections_accepted);
  page.single("sweepd_websocket_connections_open", "gauge",
              "Of the connections open now, those on the WebSocket listener.",
              server.websocket_connections_open);
  page.single("sweepd_strangers_open", "gauge",
              "Of the connections open now, those not authenticated (nor cut) yet.",
              server.strangers_open);
  page.single("sweepd_strangers_shed_total", "counter",
              "Unauthenticated connections closed to make room for a newer one "
              "(--max-strangers, --max-strangers-per-address).",
              traffic.strangers_shed);
  page.single("sweepd_auth_failures_total", "counter", "Hello tokens compared and found wrong.",
              traffic.auth_failures);
  page.single("sweepd_auth_backoff_refusals_total", "counter",
              "Hellos refused without comparing their token: their address waits after too "
              "many wrong ones (--auth-free-failures, --auth-backoff-ms).",
              traffic.auth_backoff_refusals);
  page.single("sweepd_poses_waiting", "gauge",
              "Poses queued behind a running one, all connections (the queue depth).",
              server.poses_waiting);
  page.single("sweepd_poses_running", "gauge", "Poses being deformed or rendered now.",
              server.poses_running);
  page.single("sweepd_buffered_bytes", "gauge",
              "Bytes of frames being read and replies waiting, all connections.",
              server.buffered_bytes);
  page.single("sweepd_work_bytes", "gauge",
              "Bytes of working memory reserved by requests running or queued, all connections.",
              server.work_bytes);
  page.single("sweepd_work_budget_bytes", "gauge",
              "The work budget (--work-budget-bytes): the most working memory requests hold.",
              server.work_budget_bytes);
  page.single("sweepd_work_refusals_total", "counter",
              "Requests refused because their working memory did not fit the work budget.",
              server.work_refusals);
  page.single("sweepd_store_bytes", "gauge", "Bytes of the model store's files on disk.",
              server.store_bytes);
  page.single("sweepd_models_held", "gauge", "Models held (bound and servable).",
              static_cast<std::uint64_t>(server.models.size()));
  page.per_model("sweepd_model_poses_total", "Poses deformed, by model.", server.models,
                 &ModelSnapshot::poses);
  page.per_model("sweepd_model_errors_total", "Requests failed, by model.", server.models,
                 &ModelSnapshot::errors);
  const CollisionSnapshot& collision = server.collision;
  page.header("sweepd_collision_backend", "gauge",
              "Where folding finds intersecting triangle pairs (--collision): 1 for the backend "
              "in use, 0 for the other.");
  for (const gpu::CollisionBackend backend :
       {gpu::CollisionBackend::kGpu, gpu::CollisionBackend::kCpu}) {
    page.sample("sweepd_collision_backend",
                std::string("backend=\"") + gpu::to_string(backend) + "\"",
                backend == collision.backend ? "1" : "0");
  }
  page.single("sweepd_collision_gpu_fallbacks_total", "counter",
              "Poses answered with the CPU reference's pairs after a GPU collision job failed.",
              collision.gpu_fallbacks);
  if (!server.vmc.empty()) add_vmc(page, server.vmc);
}

}  // namespace

std::string format_metrics(const ServerSnapshot* server, const ProcessStats& process,
                           Readiness::Stage stage) {
  Page page;
  page.single("sweepd_ready", "gauge", "1 while /readyz answers 200 (accepting work), else 0.",
              static_cast<std::uint64_t>(stage == Readiness::Stage::kAccepting ? 1 : 0));
  page.single("sweepd_process_start_time_seconds", "gauge",
              "When the process started, in seconds since the Unix epoch.",
              process.start_time_seconds);
  page.single("sweepd_process_resident_memory_bytes", "gauge",
              "Resident memory of the process (/proc/self/statm).", process.resident_bytes);
  if (server != nullptr) add_server(page, *server);
  return page.take();
}

}  // namespace sweepd::server
