#include "io/model_load.h"

#include <array>
#include <cstdint>
#include <fstream>
#include <span>

#include "io/assimp/assimp_load.h"
#include "io/gltf/gltf_load.h"

namespace sweepd::io {

bool is_assimp_file(const std::filesystem::path& file) {
  std::array<std::uint8_t, 1024> head{};
  std::ifstream stream(file, std::ios::binary);
  if (!stream) throw LoadError(file, "cannot open the file (missing or unreadable)");
  stream.read(reinterpret_cast<char*>(head.data()), head.size());
  const std::span<const std::uint8_t> read(head.data(), static_cast<std::size_t>(stream.gcount()));
  return !assimp_model_suffix(read).empty();
}

deform::Model load_model(const std::filesystem::path& file, LoadReport* report) {
  return is_assimp_file(file) ? load_assimp(file, report) : load_gltf(file, report);
}

}  // namespace sweepd::io
