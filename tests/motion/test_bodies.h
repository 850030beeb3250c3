// The bodies the motion tests retarget onto, by name: a file under the shared data
// (SWEEPD_SHARED_DATA, e.g. "models/corpus/makehuman_child_mixamo_unity.glb"), or "mannequin",
// the procedural mannequin at 4,000 vertices (its own rig convention, made here, never absent).
// nullopt when the shared file is absent (the caller skips, naming it).
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "deform/model/model.h"
#include "io/gltf_load.h"
#include "mannequin/mannequin.h"
#include "tests/test_paths.h"

namespace sweepd::test_models {

inline constexpr const char* kMannequinBody = "mannequin";

inline std::optional<deform::Model> load_body(const std::string& name) {
  if (name == kMannequinBody) return mannequin::make_mannequin({.target_vertices = 4000});
  const std::filesystem::path file = std::filesystem::path(SWEEPD_SHARED_DATA) / name;
  if (!std::filesystem::exists(file)) return std::nullopt;
  return io::load_gltf(file);
}

}  // namespace sweepd::test_models
