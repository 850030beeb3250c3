// GltfUriPolicy: which files a glTF's external buffer and image URIs may name, decided before any
// file is opened. Two scopes:
//   - self-contained (what a client uploads to sweepd): nothing outside the file itself; only
//     the GLB binary chunk and data: URIs are read, every other URI is refused;
//   - within a directory (a --model-dir, or a local file's own folder): relative paths that
//     stay inside that directory, also after following symlinks. Refused: an absolute path,
//     any scheme (file:, http:, C:), a `..` that climbs out, a symlink that leads out, a
//     control character (NUL would cut the path short).
//
// resolve_external_uri
// Input:  policy  the scope
//         uri     a URI as tinygltf will open it: already percent-decoded ("%2e%2e/" is "../"
//                 here, '+' is ' '), never a data: URI (tinygltf decodes those itself)
// Output: the file to read (canonical: symlinks resolved, inside policy.root), or an empty
//         file and the reason it is refused, phrased for a client: it names no server path,
//         and it is the same whether the target exists or not.
#pragma once

#include <filesystem>
#include <string>

namespace sweepd::io {

struct GltfUriPolicy {
  enum class Scope { SelfContained, WithinDirectory };
  Scope scope = Scope::SelfContained;
  std::filesystem::path root;  // WithinDirectory: the only directory files may be read from

  static GltfUriPolicy self_contained() { return {Scope::SelfContained, {}}; }
  static GltfUriPolicy within(std::filesystem::path directory) {
    return {Scope::WithinDirectory, std::move(directory)};
  }
};

struct UriResolution {
  std::filesystem::path file;  // empty when refused
  std::string refusal;         // why, when refused
};

UriResolution resolve_external_uri(const GltfUriPolicy& policy, const std::string& uri);

}  // namespace sweepd::io
