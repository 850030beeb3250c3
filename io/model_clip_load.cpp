#include "io/model_clip_load.h"

#include "io/assimp/assimp_clip_load.h"
#include "io/assimp/assimp_load.h"
#include "io/files/file_bytes.h"
#include "io/gltf/gltf_clip_load.h"
#include "io/model_load.h"

namespace sweepd::io {

motion::Clip load_model_clip(const std::filesystem::path& file, const std::string& clip) {
  if (!is_assimp_file(file)) return load_gltf_clip(file, clip);
  return load_assimp_clip(read_file_bytes(file), file, clip);
}

motion::Clip load_model_clip(std::span<const std::uint8_t> bytes,
                             const std::filesystem::path& label, const std::string& clip) {
  if (assimp_model_suffix(bytes).empty()) return load_gltf_clip(bytes, label, clip);
  return load_assimp_clip(bytes, label, clip);
}

std::vector<FileAnimation> load_model_animations(const std::filesystem::path& file) {
  if (!is_assimp_file(file)) return load_gltf_animations(file);
  return load_assimp_animations(read_file_bytes(file), file);
}

}  // namespace sweepd::io
