#include "io/gltf/gltf_uri_policy.h"

#include <algorithm>
#include <cctype>
#include <system_error>

namespace sweepd::io {

namespace {

namespace fs = std::filesystem;

UriResolution refuse(std::string reason) { return {{}, std::move(reason)}; }

bool has_control_character(const std::string& uri) {
  return std::any_of(uri.begin(), uri.end(), [](char c) {
    const auto byte = static_cast<unsigned char>(c);
    return byte < 0x20 || byte == 0x7f;
  });
}

// RFC 3986: scheme = ALPHA *( ALPHA / DIGIT / "+" / "-" / "." ) ":" — "file:", "http:", and a
// Windows drive "C:" all match; a relative path has no ':' before its first '/'.
bool has_scheme(const std::string& uri) {
  const std::size_t colon = uri.find(':');
  if (colon == std::string::npos || colon == 0 || colon > uri.find('/')) return false;
  if (!std::isalpha(static_cast<unsigned char>(uri[0]))) return false;
  return std::all_of(uri.begin() + 1, uri.begin() + colon, [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '+' || c == '-' || c == '.';
  });
}

// Component by component, so that /models-old is not inside /models.
bool starts_with_components(const fs::path& path, const fs::path& prefix) {
  auto part = path.begin();
  for (const fs::path& expected : prefix) {
    if (part == path.end() || *part != expected) return false;
    ++part;
  }
  return true;
}

}  // namespace

UriResolution resolve_external_uri(const GltfUriPolicy& policy, const std::string& uri) {
  if (policy.scope == GltfUriPolicy::Scope::SelfContained)
    return refuse("only the GLB binary chunk and data: URIs may be read (self-contained glTF)");
  if (uri.empty()) return refuse("it names no file");
  if (has_control_character(uri)) return refuse("it contains a control character");
  if (has_scheme(uri)) return refuse("it has a scheme (file:, http:, ...); only relative paths");
  const fs::path relative(uri);
  if (uri.front() == '/' || relative.is_absolute())
    return refuse("it is an absolute path; only relative paths");
  const fs::path normal = relative.lexically_normal();
  if (!normal.empty() && *normal.begin() == "..")
    return refuse("it leads out of the model's directory (..)");
  std::error_code error;
  const fs::path root = fs::weakly_canonical(fs::absolute(policy.root), error);
  if (error) return refuse("the model's directory cannot be resolved");
  // Symlinks are followed here, once, and the result is what gets opened.
  const fs::path file = fs::weakly_canonical(root / normal, error);
  if (error) return refuse("it cannot be resolved inside the model's directory");
  if (!starts_with_components(file, root))
    return refuse("it resolves outside the model's directory (a symlink leads out)");
  return {file, {}};
}

}  // namespace sweepd::io
