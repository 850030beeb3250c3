// GltfGuardedFiles: the file-system callbacks sweepd gives tinygltf in place of its own, so that
// no code path in tinygltf (buffers, images, its extra lookup in the working directory) checks,
// opens or reads a file that a GltfUriPolicy does not allow. Every path tinygltf asks about is
// turned back into the (percent-decoded) URI the glTF wrote, resolved by resolve_external_uri,
// and only an allowed file is looked at (stat) or read. The first refusal is kept, so that the
// loader can fail naming that URI. Writing is always refused (loading writes nothing).
//
// Input:  policy         the scope (copied)
// Output: base_dir()     the base directory to give tinygltf's Load*From* calls
//         callbacks()    tinygltf::FsCallbacks bound to this object (keep it alive and in place
//                        while tinygltf runs; it cannot be copied or moved)
//         refusal()      after loading: a sentence naming the first refused URI (escaped,
//                        at most 200 bytes of it) and why; empty when nothing was refused
#pragma once

#include <tiny_gltf.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "io/gltf/gltf_uri_policy.h"

namespace sweepd::io {

class GltfGuardedFiles {
 public:
  explicit GltfGuardedFiles(GltfUriPolicy policy);
  GltfGuardedFiles(const GltfGuardedFiles&) = delete;
  GltfGuardedFiles& operator=(const GltfGuardedFiles&) = delete;

  const std::string& base_dir() const { return base_dir_; }
  tinygltf::FsCallbacks callbacks();
  std::string refusal() const;

 private:
  static bool file_exists(const std::string& path, void* self);
  static std::string expand_file_path(const std::string& path, void* self);
  static bool read_whole_file(std::vector<unsigned char>* out, std::string* error,
                              const std::string& path, void* self);
  static bool write_whole_file(std::string* error, const std::string& path,
                               const std::vector<unsigned char>& bytes, void* self);

  // The file tinygltf's `path` may be read as; empty when refused (the first refusal is kept).
  std::filesystem::path allowed_file(const std::string& path);

  GltfUriPolicy policy_;
  std::string base_dir_;
  std::optional<std::string> refused_uri_;
  std::string refusal_;
};

}  // namespace sweepd::io
