// The definitions of tests/server/stored_binding.h (the library test_daemon_process).
#include "tests/server/stored_binding.h"

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

namespace sweepd::test {

std::filesystem::path stored_binding(const std::filesystem::path& store, const std::string& name) {
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

std::filesystem::path stored_binding(const std::filesystem::path& store, std::uint32_t handle) {
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
