// HaproxyProcess: Debian's haproxy run by a test on loopback from a real config file — e.g.
// deploy/haproxy.cfg — with its addresses replaced: the first `bind` line listens on
// 127.0.0.1:<free port>, the backend's `server` lines are replaced by one per Replica
// (127.0.0.1:protocol_port, health-checked on its http_port), `stats socket` moves into the
// test's directory and logs go to stderr (captured). Everything else — balance, checks, slow
// start, timeouts — stays the file's.
//
// HaproxyProcess(source, directory, replicas, backend): writes directory/haproxy.cfg and runs
//   `haproxy -db -f` on it; running() once the frontend accepts (else log() says why).
//   port(): the frontend port. Used by tests and by bench/fleet_bench.
// server_states(): each server's status from the runtime API's `show stat` ("UP", "DOWN",
//   "UP 1/2", "no check", ...) by server name (replica1, replica2, ...).
// wait_for(name, status, timeout): polls server_states until that server shows that status.
// have_haproxy(): whether haproxy is on PATH (deploy/install-deps.sh installs it).
#pragma once

#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "tests/server/loopback_port.h"

namespace sweepd::test {

struct Replica {
  int protocol_port = 0;
  int http_port = 0;
};

inline bool have_haproxy() { return std::system("command -v haproxy >/dev/null 2>&1") == 0; }

class HaproxyProcess {
 public:
  HaproxyProcess(const std::filesystem::path& source, const std::filesystem::path& directory,
                 const std::vector<Replica>& replicas)
      : config_(directory / "haproxy.cfg"),
        stats_socket_(directory / "haproxy.sock"),
        log_file_(directory / "haproxy.log") {
    // The free port may be taken by another test's server before haproxy binds it; then
    // haproxy exits saying so, and it is started again on another.
    for (int attempt = 0; attempt < 3 && !running(); ++attempt) {
      port_ = free_loopback_port();
      write_config(source, replicas);
      start();
      if (!running() && log().find("cannot bind") == std::string::npos) break;
    }
  }
  ~HaproxyProcess() {
    if (pid_ > 0) {
      kill(pid_, SIGTERM);
      waitpid(pid_, nullptr, 0);
    }
  }
  HaproxyProcess(const HaproxyProcess&) = delete;
  HaproxyProcess& operator=(const HaproxyProcess&) = delete;

  bool running() const { return pid_ > 0; }
  int port() const { return port_; }
  const std::filesystem::path& config() const { return config_; }
  std::string log() const {
    std::ifstream in(log_file_);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }

  // The runtime API's answer to `command` (e.g. "show stat"), empty when it does not answer.
  std::string runtime_api(const std::string& command) const {
    const int fd = socket(AF_UNIX, SOCK_STREAM, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    std::strncpy(address.sun_path, stats_socket_.c_str(), sizeof(address.sun_path) - 1);
    std::string answer;
    if (connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) == 0) {
      const std::string line = command + "\n";
      if (send(fd, line.data(), line.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(line.size())) {
        char chunk[4096];
        while (true) {
          const ssize_t n = recv(fd, chunk, sizeof(chunk), 0);
          if (n <= 0) break;
          answer.append(chunk, static_cast<std::size_t>(n));
        }
      }
    }
    close(fd);
    return answer;
  }

  // `show stat` is CSV: "# pxname,svname,qcur,...,status,..." then one line per proxy/server.
  std::map<std::string, std::string> server_states() const {
    std::map<std::string, std::string> states;
    std::istringstream lines(runtime_api("show stat"));
    std::vector<std::string> header;
    for (std::string line; std::getline(lines, line);) {
      std::vector<std::string> fields;
      std::istringstream cells(line.starts_with("# ") ? line.substr(2) : line);
      for (std::string cell; std::getline(cells, cell, ',');) fields.push_back(cell);
      if (line.starts_with("# ")) {
        header = fields;
        continue;
      }
      std::map<std::string, std::string> row;
      for (std::size_t i = 0; i < fields.size() && i < header.size(); ++i)
        row[header[i]] = fields[i];
      if (row["svname"] != "FRONTEND" && row["svname"] != "BACKEND" && !row["svname"].empty()) {
        states[row["svname"]] = row["status"];
      }
    }
    return states;
  }

  bool wait_for(const std::string& server, const std::string& status,
                std::chrono::milliseconds timeout) const {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      if (server_states()[server] == status) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return false;
  }

 private:
  // Runs haproxy on config_; pid_ stays -1 when it exits or never accepts within 20 s.
  void start() {
    std::filesystem::remove(stats_socket_);
    const pid_t pid = fork();
    if (pid == 0) {
      std::freopen(log_file_.c_str(), "w", stderr);
      std::freopen(log_file_.c_str(), "a", stdout);
      execlp("haproxy", "haproxy", "-db", "-f", config_.c_str(), nullptr);
      _exit(127);
    }
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (std::chrono::steady_clock::now() < deadline) {
      if (loopback_accepts(port_) && std::filesystem::exists(stats_socket_)) {
        pid_ = pid;
        return;
      }
      if (waitpid(pid, nullptr, WNOHANG) == pid) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    kill(pid, SIGKILL);
    waitpid(pid, nullptr, 0);
  }

  // The source file with its addresses replaced (see the header comment).
  void write_config(const std::filesystem::path& source,
                    const std::vector<Replica>& replicas) const {
    std::ifstream in(source);
    std::ostringstream out;
    bool bound = false;
    bool servers_written = false;
    for (std::string line; std::getline(in, line);) {
      const std::size_t start = line.find_first_not_of(' ');
      const std::string directive = start == std::string::npos ? "" : line.substr(start);
      const std::string indent(start == std::string::npos ? 0 : start, ' ');
      if (directive.starts_with("bind ") && !bound) {
        out << indent << "bind 127.0.0.1:" << port_ << "\n";
        bound = true;
      } else if (directive.starts_with("stats socket ")) {
        out << indent << "stats socket " << stats_socket_.string() << " mode 600 level admin\n";
      } else if (directive.starts_with("log /")) {
        out << indent << "log stderr format raw local0\n";
      } else if (directive.starts_with("server ")) {
        if (!servers_written) {
          for (std::size_t i = 0; i < replicas.size(); ++i) {
            out << indent << "server replica" << i + 1 << " 127.0.0.1:" << replicas[i].protocol_port
                << " port " << replicas[i].http_port << "\n";
          }
          servers_written = true;
        }
      } else {
        out << line << "\n";
      }
    }
    std::ofstream(config_) << out.str();
  }

  std::filesystem::path config_, stats_socket_, log_file_;
  pid_t pid_ = -1;
  int port_ = 0;
};

}  // namespace sweepd::test
