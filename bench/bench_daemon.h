// BenchDaemon: the built sweepd as a child process of a benchmark (server_bench, fleet_bench),
// on a free port with its store in `directory`, its JSON log in directory/sweepd.log; SIGTERM
// and reaped when this goes.
//
// BenchDaemon(binary, directory, extra_args): starts `binary --port 0 --port-file ... --store-dir
//   directory/store extra_args...` (a later --store-dir in extra_args wins: replicas sharing
//   one) and waits up to 60 s for its port. Throws std::runtime_error naming the log when it
//   does not start.
// address(), port(); http_port(): the side port when extra_args hold --http-port-file
//   directory/http_port (0 otherwise); binding(): the store's first .sweepbind (the default
//   mannequin); cpu_ms(): its CPU time so far (user + system); resident_mib(): its VmRSS;
//   peak_resident_mib(): its VmHWM (the most it has been resident); pid(): its process id.
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

namespace sweepd::bench {

class BenchDaemon {
 public:
  BenchDaemon(const std::string& binary, const std::filesystem::path& directory,
              const std::vector<std::string>& extra_args);
  ~BenchDaemon();
  BenchDaemon(const BenchDaemon&) = delete;
  BenchDaemon& operator=(const BenchDaemon&) = delete;

  std::string address() const { return "127.0.0.1:" + std::to_string(port_); }
  int port() const { return port_; }
  pid_t pid() const { return pid_; }
  int http_port() const;
  std::filesystem::path binding() const;
  double cpu_ms() const;
  double resident_mib() const;
  double peak_resident_mib() const;

 private:
  std::filesystem::path directory_;
  pid_t pid_ = -1;
  int port_ = 0;
};

}  // namespace sweepd::bench
