#include "server/http/viewer_files.h"

#include <array>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <utility>

namespace sweepd::server {
namespace {

std::string content_type_of(const std::filesystem::path& name) {
  static constexpr std::array<std::pair<std::string_view, std::string_view>, 8> kTypes = {{
      {".html", "text/html; charset=utf-8"},
      {".js", "text/javascript; charset=utf-8"},
      {".css", "text/css; charset=utf-8"},
      {".json", "application/json"},
      {".map", "application/json"},
      {".svg", "image/svg+xml"},
      {".png", "image/png"},
      {".ico", "image/x-icon"},
  }};
  const std::string extension = name.extension().string();
  for (const auto& [suffix, type] : kTypes) {
    if (extension == suffix) return std::string(type);
  }
  return "application/octet-stream";
}

}  // namespace

ViewerFiles::ViewerFiles(const std::filesystem::path& directory) {
  const std::string where = "--viewer-dir " + directory.string();
  std::error_code error;
  std::filesystem::directory_iterator entries(directory, error);
  if (error) throw std::runtime_error(where + ": cannot list the folder (" + error.message() + ")");
  std::size_t total = 0;
  for (const std::filesystem::directory_entry& entry : entries) {
    if (!entry.is_regular_file()) continue;
    std::ifstream in(entry.path(), std::ios::binary);
    if (!in) throw std::runtime_error(where + ": cannot read " + entry.path().string());
    std::string bytes(std::istreambuf_iterator<char>(in), {});
    total += bytes.size();
    if (total > kMaxViewerBytes) {
      throw std::runtime_error(where + ": the files pass " + std::to_string(kMaxViewerBytes) +
                               " bytes; is this the viewer's folder?");
    }
    files_.emplace(entry.path().filename().string(),
                   ViewerFile{std::move(bytes), content_type_of(entry.path())});
  }
  if (find("index.html") == nullptr) {
    throw std::runtime_error(where + ": no index.html (the build writes the viewer to " +
                             "<build>/client_examples/web/viewer)");
  }
}

const ViewerFile* ViewerFiles::find(std::string_view name) const {
  const auto file = files_.find(name);
  return file == files_.end() ? nullptr : &file->second;
}

}  // namespace sweepd::server
