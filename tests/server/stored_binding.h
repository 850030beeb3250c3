// Where a daemon's store (server/models/model_registry.h: files named by content id) keeps a
// model's binding, for tests that read it back:
// stored_binding(store, name) — the <cid>.sweepbind whose <cid>.json label names `name`;
// stored_binding(store, handle) — the <cid>.sweepbind whose first 8 hex digits are the handle
//   (the protocol's model_id). Empty paths when the store has no such model.
// Defined in stored_binding.cpp (the library test_daemon_process), compiled once.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace sweepd::test {

std::filesystem::path stored_binding(const std::filesystem::path& store, const std::string& name);
std::filesystem::path stored_binding(const std::filesystem::path& store, std::uint32_t handle);

}  // namespace sweepd::test
