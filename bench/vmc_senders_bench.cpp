// Issue 51's VMC target: 8 senders at 60 Hz into one daemon posing the 72k mannequin, packet to
// subscriber p99 <= 5 ms and no packet backlog growth. Not a Google Benchmark: one run, figures
// printed.
//
//   vmc_senders_bench [seconds 10] [senders 8] [hz 60] [vertices 72000] [sweepd flags...]
//
// Flags after the fourth argument go to sweepd as they are (--deform-threads 1, ...).
// Starts the built sweepd (--vmc-listen on loopback, --mannequin-vertices), one subscriber
// (SubscribeStream, latest wins, sweep, float32) and `senders` threads, each its own liblo
// socket, sending a frame bundle (12 Bone/Pos of a slow sway, OK, T) every 1/hz s. A send is
// logged, under one lock, in the order the datagrams go out; on loopback the daemon numbers
// frames in that order, so the subscriber's frame `sequence` is the sequence-th send, and its
// latency is that send to the mesh received. Latest wins: frames the daemon could not deform in
// time are dropped, and only the delivered ones have a latency. The backlog is the kernel's
// receive queue of the VMC socket (/proc/net/udp rx_queue) sampled every 100 ms, and its drops.
// Where a frame's time went: sending (the logged send to lo_send_bundle's return: the sender's
// side), then, from the reply's ServerTimings, queued (from the datagram's arrival, the kernel's
// stamp, to the start of its deformation: the wait for the I/O thread, for the subscriber's
// previous frame, for a worker) and deformed (posing and deformation), and replying, the rest
// (writing the reply, its way to the subscriber); printed for all frames and for the slowest
// 1 % (the tail the p99 target is about).
#include <lo/lo.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "bench/bench_daemon.h"
#include "bench/bench_poses.h"
#include "client/connection.h"
#include "tests/test_paths.h"

namespace {

namespace fs = std::filesystem;
namespace pb = sweepd::protocol;
using Clock = std::chrono::steady_clock;

constexpr const char* kBones[] = {"Spine",        "Chest",         "Neck",         "Head",
                                  "LeftUpperArm", "RightUpperArm", "LeftLowerArm", "RightLowerArm",
                                  "LeftUpperLeg", "RightUpperLeg", "LeftLowerLeg", "RightLowerLeg"};

// The sends in the order they went out (index: the daemon's frame number - 1).
struct SendLog {
  std::mutex lock;
  std::vector<Clock::time_point> sent;
  std::vector<Clock::time_point> returned;  // when lo_send_bundle returned
};

lo_bundle sway_frame(double seconds, int sender) {
  lo_bundle bundle = lo_bundle_new(LO_TT_IMMEDIATE);
  for (std::size_t bone = 0; bone < std::size(kBones); ++bone) {
    const double angle = 0.3 * std::sin(2.0 * seconds + static_cast<double>(bone + sender));
    lo_message message = lo_message_new();
    lo_message_add_string(message, kBones[bone]);
    for (int i = 0; i < 3; ++i) lo_message_add_float(message, 0.0f);
    lo_message_add_float(message, static_cast<float>(std::sin(angle / 2)));  // about x
    lo_message_add_float(message, 0.0f);
    lo_message_add_float(message, 0.0f);
    lo_message_add_float(message, static_cast<float>(std::cos(angle / 2)));
    lo_bundle_add_message(bundle, "/VMC/Ext/Bone/Pos", message);
  }
  lo_message ok = lo_message_new();
  lo_message_add_int32(ok, 1);
  lo_bundle_add_message(bundle, "/VMC/Ext/OK", ok);
  lo_message time = lo_message_new();
  lo_message_add_float(time, static_cast<float>(seconds));
  lo_bundle_add_message(bundle, "/VMC/Ext/T", time);
  return bundle;
}

// How long the threads of process `pid` that are alive now have waited for a CPU, runnable but
// not running (/proc/PID/task/*/schedstat, its second field), in milliseconds. Threads that
// ended (a large pose's split helpers) are not in it: a lower bound.
double run_queue_wait_ms(pid_t pid) {
  double nanoseconds = 0.0;
  std::error_code error;
  for (const auto& task : fs::directory_iterator("/proc/" + std::to_string(pid) + "/task", error)) {
    std::ifstream stat(task.path() / "schedstat");
    double running = 0.0, waiting = 0.0;
    if (stat >> running >> waiting) nanoseconds += waiting;
  }
  return 1e-6 * nanoseconds;
}

// The VMC socket's receive queue in bytes and its drops (/proc/net/udp), or {-1, -1}.
std::pair<long, long> udp_backlog(int port) {
  std::ifstream table("/proc/net/udp");
  std::string line;
  char local[16];
  std::snprintf(local, sizeof local, ":%04X", port);
  while (std::getline(table, line)) {
    std::istringstream fields(line);
    std::string slot, address, remote, state, queues, timer, retransmits, uid, timeout, inode,
        references, pointer;
    long drops = 0;
    fields >> slot >> address >> remote >> state >> queues >> timer >> retransmits >> uid >>
        timeout >> inode >> references >> pointer >> drops;
    if (address.size() < 5 || address.substr(address.size() - 5) != local) continue;
    return {std::stol(queues.substr(queues.find(':') + 1), nullptr, 16), drops};
  }
  return {-1, -1};
}

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::stod(argv[1]) : 10.0;
  const int senders = argc > 2 ? std::stoi(argv[2]) : 8;
  const double hz = argc > 3 ? std::stod(argv[3]) : 60.0;
  const int vertices = argc > 4 ? std::stoi(argv[4]) : 72000;
  const fs::path directory =
      fs::temp_directory_path() / ("vmc_senders_bench_" + std::to_string(::getpid()));
  fs::create_directories(directory);
  std::vector<std::string> daemon_flags = {
      "--vmc-listen",         "127.0.0.1:0",
      "--vmc-port-file",      (directory / "vmc_port").string(),
      "--mannequin-vertices", std::to_string(vertices),
      "--position-maps",      "0"};
  for (int flag = 5; flag < argc; ++flag) daemon_flags.emplace_back(argv[flag]);
  sweepd::bench::BenchDaemon daemon(SWEEPD_DAEMON, directory, daemon_flags);
  int vmc_port = 0;
  for (int wait = 0; wait < 600 && vmc_port == 0; ++wait) {
    std::ifstream(directory / "vmc_port") >> vmc_port;
    if (vmc_port == 0) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }

  sweepd::client::Connection subscriber(daemon.address());
  subscriber.set_receive_timeout(std::chrono::seconds(2));
  subscriber.hello("", "vmc_senders_bench", pb::PoseDelivery::LatestWins);
  flatbuffers::FlatBufferBuilder& builder = subscriber.builder();
  const auto pose = pb::add_pose(builder, pb::PoseFields{});
  subscriber.send(pb::finish_message(
      builder, pb::CreateSubscribeStream(builder, builder.CreateString("mannequin"), pose), 1));
  subscriber.expect<pb::StreamSubscribed>();

  SendLog log;
  std::vector<double> latencies_ms;
  struct Split {
    double total_ms, sending_ms, queued_ms, deform_ms;
  };
  std::vector<Split> splits;
  std::uint64_t dropped = 0;
  std::uint32_t vertex_count = 0;
  std::thread receiver([&] {
    try {
      for (;;) {
        const pb::PosedVertices& frame = subscriber.expect<pb::PosedVertices>();
        const Clock::time_point now = Clock::now();
        dropped += frame.dropped_before();
        vertex_count = frame.vertex_count();
        std::lock_guard<std::mutex> hold(log.lock);
        const std::uint64_t index = frame.sequence() - 1;
        if (index < log.sent.size()) {
          latencies_ms.push_back(
              std::chrono::duration<double, std::milli>(now - log.sent[index]).count());
          const pb::ServerTimings* timings = frame.timings();
          if (timings != nullptr) {
            // The sender's side: from the logged send to lo_send_bundle's return (the datagram
            // is in the daemon's socket by then; an upper bound, as the daemon may start on it
            // before the call returns).
            const double sending_ms =
                std::chrono::duration<double, std::milli>(log.returned[index] - log.sent[index])
                    .count();
            splits.push_back({latencies_ms.back(), sending_ms,
                              1e-6 * static_cast<double>(timings->queued_ns()),
                              1e-6 * static_cast<double>(timings->deform_ns())});
          }
        }
      }
    } catch (const std::exception&) {
      // 2 s without a frame: the senders stopped and the last frame came.
    }
  });

  const double cpu_ms_before = daemon.cpu_ms();  // start-up (binding the mannequin) aside
  const double daemon_waited_before = run_queue_wait_ms(daemon.pid());
  const double bench_waited_before = run_queue_wait_ms(::getpid());
  std::atomic<bool> stop{false};
  std::vector<std::thread> sending;
  const auto start = Clock::now();
  for (int sender = 0; sender < senders; ++sender) {
    sending.emplace_back([&, sender] {
      lo_address to = lo_address_new("127.0.0.1", std::to_string(vmc_port).c_str());
      const auto period = std::chrono::duration<double>(1.0 / hz);
      // Spread over one period, as independent senders are.
      auto next = start + std::chrono::duration_cast<Clock::duration>(period * sender / senders);
      while (!stop) {
        std::this_thread::sleep_until(next);
        const double at = std::chrono::duration<double>(Clock::now() - start).count();
        lo_bundle bundle = sway_frame(at, sender);
        {
          std::lock_guard<std::mutex> hold(log.lock);
          log.sent.push_back(Clock::now());
          lo_send_bundle(to, bundle);
          log.returned.push_back(Clock::now());
        }
        lo_bundle_free_recursive(bundle);
        next += std::chrono::duration_cast<Clock::duration>(period);
      }
      lo_address_free(to);
    });
  }
  std::vector<long> backlog_samples;
  std::pair<long, long> backlog{0, 0};
  while (Clock::now() - start < std::chrono::duration<double>(seconds)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    backlog = udp_backlog(vmc_port);
    backlog_samples.push_back(backlog.first);
  }
  stop = true;
  for (std::thread& thread : sending) thread.join();
  const double cpu_ms = daemon.cpu_ms() - cpu_ms_before;
  const double daemon_waited_ms = run_queue_wait_ms(daemon.pid()) - daemon_waited_before;
  const double bench_waited_ms = run_queue_wait_ms(::getpid()) - bench_waited_before;
  receiver.join();

  const std::size_t sent = log.sent.size();
  std::printf(
      "vmc_senders_bench: %d senders at %g Hz for %g s, the %d-vertex mannequin "
      "(%u vertices a frame), sweep\n",
      senders, hz, seconds, vertices, vertex_count);
  std::printf(
      "  frames sent %zu (%.0f/s), delivered to the subscriber %zu, dropped (latest "
      "wins) %llu\n",
      sent, static_cast<double>(sent) / seconds, latencies_ms.size(),
      static_cast<unsigned long long>(dropped));
  std::printf("  packet to subscriber: p50 %.2f ms, p99 %.2f ms, max %.2f ms\n",
              sweepd::bench::percentile(latencies_ms, 0.5),
              sweepd::bench::percentile(latencies_ms, 0.99),
              sweepd::bench::percentile(latencies_ms, 1.0));
  // The slowest 1 %: their mean time queued, deformed, and elsewhere, against all frames'.
  std::sort(splits.begin(), splits.end(),
            [](const Split& a, const Split& b) { return a.total_ms > b.total_ms; });
  const auto print_split = [&](const char* which, std::size_t count) {
    Split sum{0, 0, 0, 0};
    for (std::size_t i = 0; i < count; ++i) {
      sum.total_ms += splits[i].total_ms;
      sum.sending_ms += splits[i].sending_ms;
      sum.queued_ms += splits[i].queued_ms;
      sum.deform_ms += splits[i].deform_ms;
    }
    const double n = static_cast<double>(std::max<std::size_t>(count, 1));
    std::printf(
        "  %s (%zu frames), mean: %.2f ms = sending %.2f + queued %.2f + deformed %.2f + "
        "replying %.2f\n",
        which, count, sum.total_ms / n, sum.sending_ms / n, sum.queued_ms / n, sum.deform_ms / n,
        (sum.total_ms - sum.sending_ms - sum.queued_ms - sum.deform_ms) / n);
  };
  print_split("slowest 1 %", (splits.size() + 99) / 100);
  print_split("all", splits.size());
  // Growth: the second half's largest queue against the first half's.
  const auto half = backlog_samples.begin() + static_cast<long>(backlog_samples.size() / 2);
  const long first_half =
      half == backlog_samples.begin() ? 0 : *std::max_element(backlog_samples.begin(), half);
  const long second_half =
      half == backlog_samples.end() ? 0 : *std::max_element(half, backlog_samples.end());
  std::printf(
      "  UDP receive queue, largest: first half %ld bytes, second half %ld bytes; kernel "
      "drops %ld\n",
      first_half, second_half, backlog.second);
  std::printf("  daemon CPU while sending %.0f ms (%.0f%% of one core)\n", cpu_ms,
              100.0 * cpu_ms / (1000.0 * seconds));
  // Time runnable but not running: the machine's other work ahead of ours.
  std::printf(
      "  waiting for a CPU while sending: the daemon's threads %.0f ms (%.2f ms a frame), the "
      "bench's (senders, subscriber) %.0f ms\n",
      daemon_waited_ms, daemon_waited_ms / static_cast<double>(std::max<std::size_t>(sent, 1)),
      bench_waited_ms);
  fs::remove_all(directory);
  return 0;
}
