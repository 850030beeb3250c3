#include "bench/bench_daemon.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <stdexcept>
#include <thread>

namespace sweepd::bench {

namespace fs = std::filesystem;

BenchDaemon::BenchDaemon(const std::string& binary, const fs::path& directory,
                         const std::vector<std::string>& extra_args)
    : directory_(directory) {
  const fs::path port_file = directory / "port";
  const std::string log = (directory / "sweepd.log").string();
  std::vector<std::string> args = {binary,
                                   "--port",
                                   "0",
                                   "--port-file",
                                   port_file.string(),
                                   "--store-dir",
                                   (directory / "store").string()};
  args.insert(args.end(), extra_args.begin(), extra_args.end());
  std::vector<char*> argv;
  for (std::string& arg : args) argv.push_back(arg.data());
  argv.push_back(nullptr);
  // Its JSON log to a file, its stdout away: the bench prints only the tables.
  posix_spawn_file_actions_t streams;
  posix_spawn_file_actions_init(&streams);
  posix_spawn_file_actions_addopen(&streams, STDERR_FILENO, log.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&streams, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  const int spawned = posix_spawn(&pid_, argv[0], &streams, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&streams);
  if (spawned != 0) throw std::runtime_error("cannot start " + binary);
  for (int tries = 0; tries < 1200 && !fs::exists(port_file); ++tries) {
    if (waitpid(pid_, nullptr, WNOHANG) == pid_) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  if (!fs::exists(port_file)) throw std::runtime_error(binary + " did not start; log in " + log);
  std::ifstream(port_file) >> port_;
}

BenchDaemon::~BenchDaemon() {
  kill(pid_, SIGTERM);
  waitpid(pid_, nullptr, 0);
}

int BenchDaemon::http_port() const {
  int port = 0;
  std::ifstream(directory_ / "http_port") >> port;
  return port;
}

fs::path BenchDaemon::binding() const {
  for (const fs::directory_entry& entry : fs::directory_iterator(directory_ / "store"))
    if (entry.path().extension() == ".sweepbind") return entry.path();
  throw std::runtime_error("the daemon stored no binding in " + (directory_ / "store").string());
}

double BenchDaemon::cpu_ms() const {
  std::ifstream stat("/proc/" + std::to_string(pid_) + "/stat");
  std::string field;
  double ticks = 0.0;
  for (int i = 1; i <= 15 && stat >> field; ++i) {
    if (i >= 14) ticks += std::stod(field);  // utime, stime (fields 14, 15)
  }
  return ticks * 1000.0 / static_cast<double>(sysconf(_SC_CLK_TCK));
}

double BenchDaemon::resident_mib() const {
  std::ifstream statm("/proc/" + std::to_string(pid_) + "/statm");
  double pages = 0.0;
  statm >> pages >> pages;
  return pages * static_cast<double>(sysconf(_SC_PAGESIZE)) / (1 << 20);
}

double BenchDaemon::peak_resident_mib() const {
  std::ifstream status("/proc/" + std::to_string(pid_) + "/status");
  for (std::string line; std::getline(status, line);)
    if (line.starts_with("VmHWM:")) return std::stod(line.substr(6)) / 1024.0;
  return 0.0;
}

}  // namespace sweepd::bench
