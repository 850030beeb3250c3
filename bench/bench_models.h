// The models the bind-time benchmarks run on: the procedural mannequin at about 72k vertices
// (the paper's scale), made on first use, and the shared MakeHuman male, loaded on first use
// (nullptr where ../shared/data is absent).
#pragma once

#include <filesystem>

#include "deform/model/model.h"
#include "io/gltf/gltf_load.h"
#include "mannequin/mannequin.h"
#include "tests/test_paths.h"

namespace sweepd::bench {

inline const deform::Model& mannequin_72k() {
  static const deform::Model model = mannequin::make_mannequin({.target_vertices = 72000});
  return model;
}

inline const deform::Model* shared_male() {
  static const std::filesystem::path path =
      std::filesystem::path(SWEEPD_SHARED_DATA) / "models" / "makehuman_male_cmu.glb";
  static const deform::Model model =
      std::filesystem::exists(path) ? io::load_gltf(path) : deform::Model{};
  return model.vertex_count() > 0 ? &model : nullptr;
}

}  // namespace sweepd::bench
