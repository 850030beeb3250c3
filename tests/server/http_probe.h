// What the HTTP side port's tests ask with: have_program(name) (on PATH?), curl_get(port,
// path) — GET http://127.0.0.1:port{path} with curl, its status (0: nothing answered) and
// body — and metric(page, series), the value of one sample of a /metrics page (the series as
// printed: name and labels), -1 when absent.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

namespace sweepd::test {

inline bool have_program(const std::string& name) {
  // Appended, not "a" + name + "b": GCC 12 at -O1 takes that temporary's move for an
  // out-of-bounds copy (-Warray-bounds, a false positive).
  std::string command = "command -v ";
  command.append(name).append(" >/dev/null 2>&1");
  return std::system(command.c_str()) == 0;
}

struct HttpReply {
  int status = 0;
  std::string body;
};

// The status is the last line curl prints (-w); "000" when nothing answered.
inline HttpReply curl_get(int port, const std::string& path) {
  const std::string command =
      "curl -s --max-time 10 -w '\\n%{http_code}' 'http://127.0.0.1:" + std::to_string(port) +
      path + "'";
  FILE* pipe = popen(command.c_str(), "r");
  std::string output;
  char chunk[4096];
  while (const std::size_t n = std::fread(chunk, 1, sizeof(chunk), pipe)) output.append(chunk, n);
  pclose(pipe);
  const std::size_t last_line = output.rfind('\n');
  if (last_line == std::string::npos) return {};
  return {std::atoi(output.c_str() + last_line + 1), output.substr(0, last_line)};
}

inline double metric(const std::string& page, const std::string& series) {
  std::istringstream lines(page);
  for (std::string line; std::getline(lines, line);) {
    if (line.starts_with(series + " ")) return std::stod(line.substr(series.size() + 1));
  }
  return -1.0;
}

}  // namespace sweepd::test
