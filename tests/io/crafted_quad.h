// Small glTF files the io tests build in memory:
//   base64(bytes)   standard base64 with '=' padding, for data: URIs
//   CraftedQuad     a two-joint skinned quad as glTF JSON, its buffer embedded (to_json) or at
//                   a URI of the caller's choosing with the bytes handed back (with_buffer_uri)
#pragma once

#include <algorithm>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace sweepd::io::testing {

using nlohmann::json;

inline std::string base64(const std::string& bytes) {
  static const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t chunk = 0;
    for (std::size_t k = 0; k < 3; ++k)
      chunk = chunk << 8 | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
    for (std::size_t k = 0; k < 4; ++k)
      out += k <= n ? alphabet[(chunk >> (18 - 6 * k)) & 63] : '=';
  }
  return out;
}

// A two-joint skinned quad (4 vertices, 2 triangles) as .gltf JSON with one buffer.
// Node 0 = joint "root" at (0,1,0) with child node 2 = joint "tip" at (0,0.5,0) local; node 1 =
// the mesh. skin.joints lists the child first ([2, 0]) so the loader has to reorder them.
struct CraftedQuad {
  std::vector<float> positions = {0, 1, 0, 1, 1, 0, 1, 2, 0, 0, 2, 0};
  std::vector<std::uint8_t> joints = {1, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0};
  std::vector<float> weights = {1, 0, 0, 0, 1, 0, 0, 0, 0.5f, 0.5f, 0, 0, 1, 0, 0, 0};
  std::vector<std::uint16_t> indices = {0, 1, 2, 0, 2, 3};
  // Inverse bind matrices per skin slot: inverse world of tip (y 1.5) and root (y 1).
  std::vector<float> inverse_bind = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1.5f, 0, 1,
                                     1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1.0f, 0, 1};

  // The glTF with its one buffer embedded as a base64 data: URI.
  json to_json() const {
    std::string buffer;
    json gltf = with_buffer_uri("", buffer);
    gltf["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(buffer);
    return gltf;
  }

  // The glTF with its one buffer at `uri`; the buffer's bytes are written to `buffer`.
  json with_buffer_uri(const std::string& uri, std::string& buffer) const {
    buffer.clear();
    json views = json::array(), accessors = json::array();
    auto add = [&](const void* data, std::size_t bytes, int component, const char* type,
                   std::size_t count) {
      views.push_back({{"buffer", 0}, {"byteOffset", buffer.size()}, {"byteLength", bytes}});
      buffer.append(static_cast<const char*>(data), bytes);
      buffer.resize((buffer.size() + 3) / 4 * 4, '\0');
      accessors.push_back({{"bufferView", views.size() - 1},
                           {"componentType", component},
                           {"type", type},
                           {"count", count}});
      return accessors.size() - 1;
    };
    const auto position =
        add(positions.data(), positions.size() * 4, 5126, "VEC3", positions.size() / 3);
    const auto joint = add(joints.data(), joints.size(), 5121, "VEC4", joints.size() / 4);
    const auto weight = add(weights.data(), weights.size() * 4, 5126, "VEC4", weights.size() / 4);
    const auto index = add(indices.data(), indices.size() * 2, 5123, "SCALAR", indices.size());
    const auto bind = add(inverse_bind.data(), inverse_bind.size() * 4, 5126, "MAT4", 2);
    return {
        {"asset", {{"version", "2.0"}}},
        {"scene", 0},
        {"scenes", {{{"nodes", {0, 1}}}}},
        {"nodes",
         {{{"name", "root"}, {"translation", {0, 1, 0}}, {"children", {2}}},
          {{"mesh", 0}, {"skin", 0}},
          {{"name", "tip"}, {"translation", {0, 0.5, 0}}}}},
        {"skins", {{{"joints", {2, 0}}, {"inverseBindMatrices", bind}}}},
        {"meshes",
         {{{"primitives",
            {{{"attributes", {{"POSITION", position}, {"JOINTS_0", joint}, {"WEIGHTS_0", weight}}},
              {"indices", index}}}}}}},
        {"accessors", accessors},
        {"bufferViews", views},
        {"buffers", {{{"byteLength", buffer.size()}, {"uri", uri}}}},
    };
  }
};

}  // namespace sweepd::io::testing
