// fleet_bench: what the fleet machinery costs (issue 14 item 6). Two sweepd replicas sharing one
// store, with Debian's haproxy in front started from deploy/haproxy.cfg (addresses replaced:
// tests/server/haproxy_process.h), all on loopback, as deploy/README.md runs them.
//
//   fleet_bench [--daemon PATH] [--render-frames PATH] [--vertices N] [--poses N] [--rounds N]
//               [--frames N] [--side N] [--haproxy-config FILE ...] [--no-renders]
//
// 1. The proxy hop: one client, one pose at a time (InOrder), directly to a replica and through
//    HAProxy, in alternating rounds so that drift of the machine's load falls on both → round
//    trip p50 / p99 each, and through ÷ direct at p50 (the target: ≤ 1.10 at 72k
//    vertices); for float32 replies (850 KB at 72k) and for compact vertex streams (Meshopt,
//    protocol 1.5: about a third of the bytes for the proxy to carry, the server's encode added
//    on both paths). --haproxy-config (repeatable; default deploy/haproxy.cfg) starts
//    one HAProxy per file, each measured in the same rounds against the same direct baseline,
//    to compare configurations in one run.
// 2. Render throughput: render_frames over --frames frames of CMU clip 01_01 at --side² (position
//    and coverage, uncompressed), against one replica; against both (--server A,B); and as two
//    shards at once through HAProxy → frames per second each, and two ÷ one (target ≥ 0.9: both
//    replicas share this machine's cores, so two cannot beat one here; the ratio is what the
//    fleet machinery costs, not what a second machine would add).
// Prints Markdown tables. Exit code 1 when a part cannot be had (no haproxy, a daemon that
// does not start, a render that fails), 2 for a bad command line.
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "bench/bench_daemon.h"
#include "bench/bench_poses.h"
#include "client/connection.h"
#include "console/command_line.h"
#include "tests/server/client_run.h"
#include "tests/server/haproxy_process.h"
#include "tests/test_paths.h"

namespace {

namespace fs = std::filesystem;
namespace pb = sweepd::protocol;
using Clock = std::chrono::steady_clock;
using sweepd::bench::BenchPose;

struct Options {
  std::string daemon = SWEEPD_DAEMON, render_frames = SWEEPD_RENDER_FRAMES;
  int vertices = 72000, poses = 200, rounds = 3, frames = 40, side = 512;
  std::vector<std::string> haproxy_configs;
  bool renders = true;
};

// Round trips of `poses`, one at a time, on a new connection to `address` (after 10 warm-up
// poses), replies in `format`, appended to `times` in ms.
void round_trips(const std::string& address, const std::vector<BenchPose>& poses,
                 pb::PositionFormat format, std::vector<double>& times) {
  sweepd::client::Connection connection(address);
  connection.hello("", "fleet_bench");
  const std::uint32_t model_id = connection.load_model("mannequin").model_id();
  constexpr int kWarmUp = 10;
  for (int i = -kWarmUp; i < static_cast<int>(poses.size()); ++i) {
    const Clock::time_point start = Clock::now();
    sweepd::bench::send_pose(connection, model_id, static_cast<std::uint64_t>(i + kWarmUp + 1),
                             poses[static_cast<std::size_t>(std::max(i, 0))], std::nullopt, format);
    connection.expect<pb::PosedVertices>();
    if (i >= 0) times.push_back(sweepd::bench::milliseconds_since(start));
  }
  connection.close();
}

// Frames per second of render_frames runs started at once (each given its own flags), all
// frames counted over the wall time of the slowest; throws when one fails.
double render_rate(const Options& options, const std::vector<std::string>& runs,
                   const fs::path& output) {
  fs::remove_all(output);
  const fs::path clip = fs::path(SWEEPD_SHARED_DATA) / "motion" / "cmu_01_01.bvh";
  const std::string common = options.render_frames + " --bvh " + clip.string() + " --frames 0-" +
                             std::to_string(options.frames - 1) + " --width " +
                             std::to_string(options.side) + " --height " +
                             std::to_string(options.side) + " -o " + output.string() + " ";
  std::vector<sweepd::test::ClientRun> results(runs.size());
  const Clock::time_point start = Clock::now();
  std::vector<std::thread> threads;
  for (std::size_t r = 0; r < runs.size(); ++r)
    threads.emplace_back([&, r] { results[r] = sweepd::test::run_client(common + runs[r]); });
  for (std::thread& thread : threads) thread.join();
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  int rendered = 0;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const int frames = sweepd::test::render_counts(results[r].output)[0];
    if (results[r].exit_code != 0 || frames < 0)
      throw std::runtime_error("render_frames " + runs[r] + " failed:\n" + results[r].output);
    rendered += frames;
  }
  if (rendered != options.frames)
    throw std::runtime_error("rendered " + std::to_string(rendered) + " frames, not " +
                             std::to_string(options.frames));
  return rendered / seconds;
}

void describe(CLI::App& app, Options& o) {
  app.description(
      "What the fleet machinery costs: the HAProxy hop, and renders on 1 and 2 replicas.");
  app.add_option("--daemon", o.daemon, "the sweepd binary")->capture_default_str();
  app.add_option("--render-frames", o.render_frames, "the render_frames binary")
      ->capture_default_str();
  app.add_option("--vertices", o.vertices, "the mannequin's vertex count")
      ->check(sweepd::console::whole_number(1000, 10'000'000))
      ->capture_default_str();
  app.add_option("--poses", o.poses, "poses timed per round and path")
      ->check(sweepd::console::whole_number(1, 1'000'000))
      ->capture_default_str();
  app.add_option("--rounds", o.rounds, "rounds of direct, then through HAProxy")
      ->check(sweepd::console::whole_number(1, 1000))
      ->capture_default_str();
  app.add_option("--frames", o.frames, "frames per render")
      ->check(sweepd::console::whole_number(2, 100'000))
      ->capture_default_str();
  app.add_option("--side", o.side, "position map width and height")
      ->check(sweepd::console::whole_number(16, 8192))
      ->capture_default_str();
  app.add_option("--haproxy-config", o.haproxy_configs,
                 "an HAProxy configuration to measure (repeatable; default deploy/haproxy.cfg)")
      ->check(CLI::ExistingFile);
  app.add_flag("!--no-renders", o.renders, "only the proxy hop (part 1)");
}

// Part 2: render_frames on one replica, on both, and as two shards through HAProxy.
void render_rates(const Options& options,
                  const std::vector<std::unique_ptr<sweepd::bench::BenchDaemon>>& replicas,
                  const std::string& proxy, const fs::path& frames) {
  const std::string a = replicas[0]->address(), b = replicas[1]->address();
  const double one = render_rate(options, {"--server " + a}, frames);
  const double both = render_rate(options, {"--server " + a + "," + b}, frames);
  const double sharded = render_rate(
      options, {"--server " + proxy + " --shard 0/2", "--server " + proxy + " --shard 1/2"},
      frames);
  std::printf("| %d frames at %d², uncompressed | frames/s | ÷ one replica |\n|---|---|---|\n",
              options.frames, options.side);
  std::printf("| one replica | %.2f | 1 |\n", one);
  std::printf("| two replicas (--server A,B) | %.2f | %.3f |\n", both, both / one);
  std::printf("| two shards through HAProxy | %.2f | %.3f |\n\n", sharded, sharded / one);
}

int run_bench(const Options& options) {
  const fs::path directory =
      fs::temp_directory_path() / ("sweepd_fleet_bench_" + std::to_string(getpid()));
  fs::create_directories(directory);
  std::vector<std::unique_ptr<sweepd::bench::BenchDaemon>> replicas;
  std::vector<sweepd::test::Replica> ports;
  for (int r = 0; r < 2; ++r) {
    const fs::path home = directory / ("replica" + std::to_string(r + 1));
    fs::create_directories(home);
    replicas.push_back(std::make_unique<sweepd::bench::BenchDaemon>(
        options.daemon, home,
        std::vector<std::string>{"--store-dir", (directory / "store").string(),
                                 "--mannequin-vertices", std::to_string(options.vertices),
                                 "--http-listen", "127.0.0.1:0", "--http-port-file",
                                 (home / "http_port").string()}));
    ports.push_back({replicas.back()->port(), replicas.back()->http_port()});
  }
  std::vector<std::string> configs = options.haproxy_configs;
  if (configs.empty()) configs.push_back(fs::path(SWEEPD_SOURCE_DIR) / "deploy" / "haproxy.cfg");
  std::vector<std::unique_ptr<sweepd::test::HaproxyProcess>> proxies;
  for (std::size_t c = 0; c < configs.size(); ++c) {
    const fs::path home = directory / ("haproxy" + std::to_string(c + 1));
    fs::create_directories(home);
    proxies.push_back(std::make_unique<sweepd::test::HaproxyProcess>(configs[c], home, ports));
    sweepd::test::HaproxyProcess& haproxy = *proxies.back();
    if (!haproxy.running() || !haproxy.wait_for("replica1", "UP", std::chrono::seconds(15)) ||
        !haproxy.wait_for("replica2", "UP", std::chrono::seconds(15))) {
      std::fprintf(stderr, "fleet_bench: haproxy (%s) did not serve both replicas:\n%s\n",
                   configs[c].c_str(), haproxy.log().c_str());
      return 1;
    }
  }
  const std::string proxy = "127.0.0.1:" + std::to_string(proxies.front()->port());

  std::vector<BenchPose> poses;
  std::uint32_t vertex_count = 0;
  {
    sweepd::client::Connection connection(replicas[0]->address());
    connection.hello("", "fleet_bench");
    const pb::ModelInfo& info = connection.load_model("mannequin");
    vertex_count = info.vertex_count();
    poses = sweepd::bench::clip_poses(info, options.poses);
    connection.close();
  }
  using sweepd::bench::percentile;
  std::printf(
      "| %u vertices, %d × %d poses | direct p50 ms | p99 ms | through HAProxy p50 ms | "
      "p99 ms | through ÷ direct p50 |\n|---|---|---|---|---|---|\n",
      vertex_count, options.rounds, options.poses);
  const std::pair<pb::PositionFormat, const char*> formats[] = {
      {pb::PositionFormat::Float32, "float32"}, {pb::PositionFormat::Meshopt, "Meshopt"}};
  for (const auto& [format, format_name] : formats) {
    std::vector<double> direct;
    std::vector<std::vector<double>> through(proxies.size());
    for (int round = 0; round < options.rounds; ++round) {
      round_trips(replicas[0]->address(), poses, format, direct);
      for (std::size_t c = 0; c < proxies.size(); ++c)
        round_trips("127.0.0.1:" + std::to_string(proxies[c]->port()), poses, format, through[c]);
    }
    for (std::size_t c = 0; c < proxies.size(); ++c) {
      std::printf("| %s replies%s%s | %.3f | %.3f | %.3f | %.3f | %.3f |\n", format_name,
                  configs.size() == 1 ? "" : ", ", configs.size() == 1 ? "" : configs[c].c_str(),
                  percentile(direct, 0.5), percentile(direct, 0.99), percentile(through[c], 0.5),
                  percentile(through[c], 0.99),
                  percentile(through[c], 0.5) / percentile(direct, 0.5));
    }
  }
  std::printf("\n");
  std::fflush(stdout);
  if (options.renders) render_rates(options, replicas, proxy, directory / "frames");
  std::printf("%u cores; load average at the end: ", std::thread::hardware_concurrency());
  double load = 0.0;
  std::ifstream("/proc/loadavg") >> load;
  std::printf("%.2f\n", load);
  proxies.clear();
  replicas.clear();
  fs::remove_all(directory);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  CLI::App app("", "fleet_bench");
  describe(app, options);
  if (const std::optional<int> exit_code = sweepd::console::parse_command_line(app, argc, argv))
    return *exit_code;
  try {
    return run_bench(options);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "fleet_bench: %s\n", error.what());
    return 1;
  }
}
