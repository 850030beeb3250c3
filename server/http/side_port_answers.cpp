#include "server/http/side_port_answers.h"

#include "server/handlers/client_string_limits.h"

namespace sweepd::server {
namespace {

const char* reason_phrase(int status) {
  switch (status) {
    case 200:
      return "OK";
    case 400:
      return "Bad Request";
    case 404:
      return "Not Found";
    case 405:
      return "Method Not Allowed";
    case 408:
      return "Request Timeout";
    case 414:
      return "URI Too Long";
    case 431:
      return "Request Header Fields Too Large";
    case 503:
      return "Service Unavailable";
    default:
      return "Unknown";
  }
}

HttpAnswer viewer_answer(std::string_view path, const ViewerFiles* viewer) {
  // "/viewer", "/viewer/" and "/viewer/NAME" (NAME without '/'); index.html by default.
  std::string_view name = path.substr(std::string_view("/viewer").size());
  if (name.starts_with('/')) name.remove_prefix(1);
  if (name.find('/') != std::string_view::npos) return {404, kPlainText, "not found\n", {}};
  const std::string file_name = name.empty() ? std::string("index.html") : std::string(name);
  // The name is echoed below: a name longer than any viewer file's is refused unechoed.
  if (file_name.size() > kMaxNameBytes) {
    return {414,
            kPlainText,
            "the viewer file name has " + std::to_string(file_name.size()) +
                " bytes; the limit is " + std::to_string(kMaxNameBytes) + " bytes\n",
            {}};
  }
  // The name is looked up among the files read at start-up; it never reaches the file system.
  const ViewerFile* file = viewer != nullptr ? viewer->find(file_name) : nullptr;
  if (file == nullptr) {
    return {404,
            kPlainText,
            viewer == nullptr ? "no viewer here: sweepd serves /viewer when started with "
                                "--viewer-dir DIR (the build's client_examples/web/viewer)\n"
                              : "no file '" + file_name + "' in the viewer\n",
            {}};
  }
  return {200,
          file->content_type,
          file->bytes,
          {{"Cache-Control", "no-cache"}, {"X-Content-Type-Options", "nosniff"}}};
}

}  // namespace

std::optional<HttpAnswer> answer_at_once(const HttpRequestHead& head, const Readiness& readiness,
                                         const ViewerFiles* viewer) {
  if (head.method != "GET" && head.method != "HEAD") {
    return HttpAnswer{
        405, kPlainText, "the side port answers GET and HEAD only\n", {{"Allow", "GET, HEAD"}}};
  }
  if (head.path == "/healthz") return HttpAnswer{200, kPlainText, "ok\n", {}};
  if (head.path == "/readyz") {
    const Readiness::Stage stage = readiness.stage();
    return HttpAnswer{stage == Readiness::Stage::kAccepting ? 200 : 503,
                      kPlainText,
                      std::string(Readiness::describe(stage)) + "\n",
                      {}};
  }
  if (head.path == "/metrics") return std::nullopt;
  if (head.path == "/viewer" || head.path.starts_with("/viewer/")) {
    return viewer_answer(head.path, viewer);
  }
  return HttpAnswer{404, kPlainText, "not found\n", {}};
}

std::string http_response_bytes(const HttpAnswer& answer, bool head_only) {
  std::string bytes = "HTTP/1.1 " + std::to_string(answer.status) + " " +
                      reason_phrase(answer.status) + "\r\nContent-Type: " + answer.content_type +
                      "\r\nContent-Length: " + std::to_string(answer.body.size()) +
                      "\r\nConnection: close\r\n";
  for (const auto& [name, value] : answer.headers) bytes += name + ": " + value + "\r\n";
  bytes += "\r\n";
  if (!head_only) bytes += answer.body;
  return bytes;
}

}  // namespace sweepd::server
