// Where a daemon's store (server/models/model_registry.h: files named by content id) keeps a
// model's binding, for tests that read it back:
// stored_binding(store, name) — the <cid>.sweepbind whose <cid>.json label names `name`;
// stored_binding(store, handle) — the <cid>.sweepbind whose first 8 hex digits are the handle
//   (the protocol's model_id). Empty paths when the store has no such model.
#pragma once

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

namespace sweepd::test {

inline std::filesystem::path stored_binding(const std::filesystem::path& store,
                                            const std::string& name) {
  for (const auto& entry : std::filesystem::directory_iterator(store)) {
    const std::filesystem::path label = entry.path();
    if (label.extension() != ".json" || label.stem().string().size() != 64) continue;
    std::ifstream in(label);
    const nlohmann::json parsed = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
    if (parsed.is_object() && parsed.value("name", "") == name)
      return store / (label.stem().string() + ".sweepbind");
  }
  return {};
}

inline std::filesystem::path stored_binding(const std::filesystem::path& store,
                                            std::uint32_t handle) {
  char prefix[9];
  std::snprintf(prefix, sizeof prefix, "%08x", handle);
  for (const auto& entry : std::filesystem::directory_iterator(store)) {
    const std::string name = entry.path().filename().string();
    if (entry.path().extension() == ".sweepbind" && name.size() == 64 + 10 &&
        name.starts_with(prefix))
      return entry.path();
  }
  return {};
}

}  // namespace sweepd::test
