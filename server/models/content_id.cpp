#include "server/models/content_id.h"

#include <openssl/evp.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <stdexcept>

namespace sweepd::server {
namespace {

// SHA-256 over parts, each preceded by its length (8 bytes, little-endian), so that no two
// different lists of parts hash the same bytes; the first part says what the rest mean.
std::string sha256_hex(std::initializer_list<std::span<const std::uint8_t>> parts) {
  const std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)> context(EVP_MD_CTX_new(),
                                                                        &EVP_MD_CTX_free);
  if (!context || EVP_DigestInit_ex(context.get(), EVP_sha256(), nullptr) != 1)
    throw std::runtime_error("SHA-256 is not available from OpenSSL");
  for (const std::span<const std::uint8_t> part : parts) {
    std::uint8_t length[8];
    for (int i = 0; i < 8; ++i) length[i] = static_cast<std::uint8_t>(part.size() >> (8 * i));
    EVP_DigestUpdate(context.get(), length, sizeof length);
    EVP_DigestUpdate(context.get(), part.data(), part.size());
  }
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int size = 0;
  EVP_DigestFinal_ex(context.get(), digest, &size);
  static constexpr char kHex[] = "0123456789abcdef";
  std::string hex;
  for (unsigned int i = 0; i < size; ++i) {
    hex += kHex[digest[i] >> 4];
    hex += kHex[digest[i] & 15];
  }
  return hex;
}

std::span<const std::uint8_t> bytes_of(std::string_view text) {
  return {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()};
}

}  // namespace

std::string model_content_id(std::span<const std::uint8_t> source, std::string_view rig_map_json,
                             int keys_per_link, int orientation) {
  // The linear curve (0) adds nothing, so ids made before the orientation option stay valid.
  const std::string options =
      "keys_per_link=" + std::to_string(keys_per_link) +
      (orientation != 0 ? ",orientation=" + std::to_string(orientation) : "");
  return sha256_hex({bytes_of("sweepd model v1: glTF, rig map, options"), source,
                     bytes_of(rig_map_json), bytes_of(options)});
}

std::string described_content_id(std::string_view description) {
  return sha256_hex({bytes_of("sweepd model v1: described"), bytes_of(description)});
}

std::string clip_content_id(std::string_view bvh, float length_scale,
                            std::string_view joint_name_map) {
  char scale[32];
  std::snprintf(scale, sizeof scale, "length_scale=%a", static_cast<double>(length_scale));
  if (joint_name_map.empty())  // the ids of clips without a map are those of protocol 1.4
    return sha256_hex({bytes_of("sweepd clip v1: BVH, options"), bytes_of(bvh), bytes_of(scale)});
  return sha256_hex({bytes_of("sweepd clip v1: BVH, options"), bytes_of(bvh), bytes_of(scale),
                     bytes_of("joint_name_map="), bytes_of(joint_name_map)});
}

std::string gltf_clip_content_id(std::span<const std::uint8_t> gltf, std::string_view animation,
                                 bool own_skeleton, std::string_view joint_name_map) {
  return sha256_hex({bytes_of("sweepd clip v1: glTF animation, options"), gltf, bytes_of(animation),
                     bytes_of(own_skeleton ? "own_skeleton" : "retargeted"),
                     bytes_of(joint_name_map)});
}

std::string range_of_motion_clip_id(std::string_view model_content_id) {
  return sha256_hex(
      {bytes_of("sweepd clip v1: range of motion of a model"), bytes_of(model_content_id)});
}

std::uint32_t handle_of(std::string_view content_id) {
  const std::uint32_t handle =
      static_cast<std::uint32_t>(std::stoul(std::string(content_id.substr(0, 8)), nullptr, 16));
  return handle == 0 ? 1 : handle;
}

bool is_content_id(std::string_view text) {
  return text.size() == 64 && std::all_of(text.begin(), text.end(), [](char c) {
           return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
         });
}

}  // namespace sweepd::server
