// fuzz_http (fuzz/fuzz_inputs.h): the HTTP side port's request heads. Apart from the other entry
// points, it needs nothing but server/http's head reader and answers (no model, no server), so
// that its fuzzer can be built from those files alone.
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <string_view>

#include "fuzz/fuzz_inputs.h"
#include "server/http/http_request_head.h"
#include "server/http/side_port_answers.h"
#include "server/http/viewer_files.h"

namespace sweepd::fuzz {
namespace {

namespace fs = std::filesystem;

// A viewer of two files, read once from a folder of this process (removed at once), so that
// /viewer names are looked up among files as the side port looks them up.
const server::ViewerFiles& viewer() {
  static const server::ViewerFiles files = [] {
    const fs::path directory =
        fs::temp_directory_path() / ("sweepd_fuzz_viewer_" + std::to_string(getpid()));
    fs::create_directories(directory);
    std::ofstream(directory / "index.html") << "<!doctype html><title>viewer</title>";
    std::ofstream(directory / "viewer.js") << "export {};";
    server::ViewerFiles read(directory);
    fs::remove_all(directory);
    return read;
  }();
  return files;
}

}  // namespace

bool fuzz_http(std::span<const std::uint8_t> bytes) {
  if (bytes.empty()) return false;
  // The first byte sets how the bytes arrive: 1 to 256 at a time; the side port reads the
  // head again from its start after each read, as here.
  const std::size_t piece = static_cast<std::size_t>(bytes[0]) + 1;
  const std::string_view received(reinterpret_cast<const char*>(bytes.data()) + 1,
                                  bytes.size() - 1);
  static const server::Readiness readiness;  // restoring the store: /readyz answers 503
  for (std::size_t at = 0;;) {
    at = std::min(at + piece, received.size());
    const server::HttpRequestHead head =
        server::read_request_head(received.substr(0, at), server::kMaxRequestHeadBytes);
    if (head.status == server::HttpRequestHead::Status::kComplete) {
      // /metrics is answered on its own thread from the server's counters: not reached here.
      if (const auto answer = server::answer_at_once(head, readiness, &viewer())) {
        const std::string response = server::http_response_bytes(*answer, head.method == "HEAD");
        if (!response.starts_with("HTTP/1.1 ")) throw std::logic_error("no status line");
      }
      return true;
    }
    if (head.status != server::HttpRequestHead::Status::kIncomplete || at == received.size()) {
      return false;
    }
  }
}

}  // namespace sweepd::fuzz
