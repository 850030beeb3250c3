#include "io/gltf/gltf_accessors.h"

#include <cstdint>
#include <cstring>

#include "io/files/file_bytes.h"
#include "io/gltf/gltf_guarded_files.h"

namespace sweepd::io::gltf {

namespace {

std::string trimmed(std::string text) {
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.pop_back();
  return text;
}

template <typename T>
double decode_as(const unsigned char* bytes) {
  T value;
  std::memcpy(&value, bytes, sizeof(T));
  return static_cast<double>(value);
}

bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                const unsigned char*, int, void*) {
  return true;  // textures play no part in deformation; do not decode them
}

}  // namespace

std::string type_name(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return "SCALAR";
    case TINYGLTF_TYPE_VEC2:
      return "VEC2";
    case TINYGLTF_TYPE_VEC3:
      return "VEC3";
    case TINYGLTF_TYPE_VEC4:
      return "VEC4";
    case TINYGLTF_TYPE_MAT4:
      return "MAT4";
    default:
      return "type " + std::to_string(type);
  }
}

double max_of_integer_type(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
      return 127.0;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 255.0;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
      return 32767.0;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 65535.0;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      return 4294967295.0;
    default:
      return 1.0;
  }
}

double decode_component(const unsigned char* bytes, int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
      return decode_as<std::int8_t>(bytes);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return decode_as<std::uint8_t>(bytes);
    case TINYGLTF_COMPONENT_TYPE_SHORT:
      return decode_as<std::int16_t>(bytes);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return decode_as<std::uint16_t>(bytes);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      return decode_as<std::uint32_t>(bytes);
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return decode_as<float>(bytes);
    default:
      return 0.0;
  }
}

tinygltf::Model parse_gltf_file(const fs::path& file, const GltfUriPolicy& uris,
                                LoadReport* report) {
  return parse_gltf_bytes(read_file_bytes(file), file, uris, report);
}

tinygltf::Model parse_gltf_bytes(std::span<const unsigned char> bytes, const fs::path& file,
                                 const GltfUriPolicy& uris, LoadReport* report) {
  if (bytes.empty()) throw LoadError(file, "the file is empty");
  const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  if (binary) {
    std::uint32_t declared = 0;
    if (bytes.size() >= 12) std::memcpy(&declared, bytes.data() + 8, 4);
    if (bytes.size() < 12)
      throw LoadError(file, "not a valid .glb: truncated inside the 12-byte header");
    if (declared > bytes.size())
      throw LoadError(file, "not a valid .glb: truncated (the header declares " +
                                std::to_string(declared) + " bytes, the file has " +
                                std::to_string(bytes.size()) + ")");
  }
  tinygltf::TinyGLTF parser;
  parser.SetImageLoader(skip_image, nullptr);
  GltfGuardedFiles files(uris);
  parser.SetFsCallbacks(files.callbacks());
  tinygltf::Model gltf;
  std::string error, warning;
  const std::string& base_dir = files.base_dir();
  const bool ok =
      binary ? parser.LoadBinaryFromMemory(&gltf, &error, &warning, bytes.data(),
                                           static_cast<unsigned int>(bytes.size()), base_dir)
             : parser.LoadASCIIFromString(&gltf, &error, &warning,
                                          reinterpret_cast<const char*>(bytes.data()),
                                          static_cast<unsigned int>(bytes.size()), base_dir);
  // Before tinygltf's own message, which may just say "File not found", and also when only an
  // image was refused (tinygltf merely warns about images).
  if (std::string refusal = files.refusal(); !refusal.empty()) throw LoadError(file, refusal);
  if (!ok) {
    std::string reason = trimmed(error.empty() ? warning : error);
    if (reason.empty()) reason = "malformed glTF (e.g. a non-integer where an index belongs)";
    if (reason.find("parse_error") != std::string::npos) reason = "invalid JSON: " + reason;
    throw LoadError(file,
                    std::string(binary ? "not a valid .glb" : "not a valid .gltf") + ": " + reason);
  }
  if (report && !trimmed(warning).empty()) report->warnings.push_back(trimmed(warning));
  return gltf;
}

}  // namespace sweepd::io::gltf
