// ViewerFiles: the browser viewer's files (the build's client_examples/web/viewer folder), read
// into memory once at start-up from the folder the operator names (--viewer-dir), so that the
// HTTP side port serves GET /viewer from memory: no request ever names a path on disk, and
// nothing written to the folder later is served.
//
// Input: `directory`, whose regular files directly inside it (not in subfolders) are read,
// at most kMaxViewerBytes together; it must hold index.html. Throws std::runtime_error naming
// the folder or file and the reason (missing, unreadable, no index.html, too large).
// find(name): the file called `name` (e.g. "viewer.js"), with its Content-Type; nullptr when
// there is none.
#pragma once

#include <cstddef>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>

namespace sweepd::server {

inline constexpr std::size_t kMaxViewerBytes = 64u << 20;

struct ViewerFile {
  std::string bytes;
  std::string content_type;  // from the name's extension; application/octet-stream otherwise
};

class ViewerFiles {
 public:
  explicit ViewerFiles(const std::filesystem::path& directory);

  const ViewerFile* find(std::string_view name) const;

 private:
  std::map<std::string, ViewerFile, std::less<>> files_;
};

}  // namespace sweepd::server
