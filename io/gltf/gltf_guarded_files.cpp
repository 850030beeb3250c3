#include "io/gltf/gltf_guarded_files.h"

#include <cstdio>
#include <fstream>
#include <iterator>
#include <system_error>
#include <utility>

namespace sweepd::io {

namespace {

namespace fs = std::filesystem;

// A URI comes from a stranger: show at most this much of it, with quotes, backslashes and
// control characters escaped, so the message stays one readable line of bounded length.
constexpr std::size_t kMaxShownUriBytes = 200;

std::string escaped(const std::string& uri) {
  std::string shown;
  for (std::size_t i = 0; i < uri.size() && i < kMaxShownUriBytes; ++i) {
    const auto byte = static_cast<unsigned char>(uri[i]);
    if (byte == '"' || byte == '\\') {
      shown += '\\';
      shown += static_cast<char>(byte);
    } else if (byte < 0x20 || byte == 0x7f) {
      char code[5];
      std::snprintf(code, sizeof(code), "\\x%02x", byte);
      shown += code;
    } else {
      shown += static_cast<char>(byte);
    }
  }
  if (uri.size() > kMaxShownUriBytes) shown += "...";
  return shown;
}

}  // namespace

GltfGuardedFiles::GltfGuardedFiles(GltfUriPolicy policy) : policy_(std::move(policy)) {
  if (policy_.scope == GltfUriPolicy::Scope::WithinDirectory)
    base_dir_ = fs::absolute(policy_.root).string();
}

tinygltf::FsCallbacks GltfGuardedFiles::callbacks() {
  return {&file_exists, &expand_file_path, &read_whole_file, &write_whole_file, this};
}

std::string GltfGuardedFiles::refusal() const {
  if (!refused_uri_) return {};
  return "external URI \"" + escaped(*refused_uri_) + "\" refused: " + refusal_;
}

fs::path GltfGuardedFiles::allowed_file(const std::string& path) {
  std::string uri = path;  // self-contained: the base directory is empty, so path is the URI
  if (policy_.scope == GltfUriPolicy::Scope::WithinDirectory) {
    const std::string prefix = base_dir_.ends_with('/') ? base_dir_ : base_dir_ + "/";
    // tinygltf tries base_dir/uri, then ./uri in the working directory: only the first is
    // the glTF's own folder; the second is refused without a word (the first one spoke).
    if (!path.starts_with(prefix)) return {};
    uri = path.substr(prefix.size());
  }
  UriResolution resolution = resolve_external_uri(policy_, uri);
  if (resolution.file.empty() && !refused_uri_) {
    refused_uri_ = uri;
    refusal_ = std::move(resolution.refusal);
  }
  return resolution.file;
}

bool GltfGuardedFiles::file_exists(const std::string& path, void* self) {
  const fs::path file = static_cast<GltfGuardedFiles*>(self)->allowed_file(path);
  std::error_code error;
  return !file.empty() && fs::is_regular_file(file, error);  // stat only, no open
}

std::string GltfGuardedFiles::expand_file_path(const std::string& path, void*) {
  return path;  // no ~ or $VARIABLE expansion: a URI means what it says
}

bool GltfGuardedFiles::read_whole_file(std::vector<unsigned char>* out, std::string* error,
                                       const std::string& path, void* self) {
  const fs::path file = static_cast<GltfGuardedFiles*>(self)->allowed_file(path);
  std::error_code status;
  if (file.empty() || !fs::is_regular_file(file, status)) {
    if (error) *error += "refused";
    return false;
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    if (error) *error += "cannot be read";
    return false;
  }
  out->assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return true;
}

bool GltfGuardedFiles::write_whole_file(std::string* error, const std::string&,
                                        const std::vector<unsigned char>&, void*) {
  if (error) *error += "loading a glTF writes no file";
  return false;
}

}  // namespace sweepd::io
