// The bodies the motion tests retarget onto, by name: a file under the shared data
// (SWEEPD_SHARED_DATA, e.g. "models/corpus/makehuman_child_mixamo_unity.glb"), or "mannequin",
// the procedural mannequin at 4,000 vertices (its own rig convention, made here, never absent).
// nullopt when the shared file is absent (the caller skips, naming it).
// Body: a value-parameterized test's body (name and whether mirrored), loaded by load_body and
// named for gtest by body_test_name ("makehuman_male_cmu_mirrored", "mannequin"); every_body
// lists them.
#pragma once

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "deform/model/model.h"
#include "io/gltf/gltf_load.h"
#include "mannequin/mannequin.h"
#include "tests/mirrored_model.h"
#include "tests/test_paths.h"

namespace sweepd::test_models {

inline constexpr const char* kMannequinBody = "mannequin";

inline std::optional<deform::Model> load_body(const std::string& name) {
  if (name == kMannequinBody) return mannequin::make_mannequin({.target_vertices = 4000});
  const std::filesystem::path file = std::filesystem::path(SWEEPD_SHARED_DATA) / name;
  if (!std::filesystem::exists(file)) return std::nullopt;
  return io::load_gltf(file);
}

struct Body {
  const char* file;  // load_body's name
  bool mirror;
};

inline std::optional<deform::Model> load_body(const Body& body) {
  std::optional<deform::Model> model = load_body(body.file);
  if (model && body.mirror) model = mirrored(std::move(*model));
  return model;
}

// Every shared body issue 48 names, and the mannequin: the male (also mirrored where asked),
// the RiggedFigure, the four corpus bodies.
inline std::vector<Body> every_body(bool and_the_male_mirrored = false) {
  std::vector<Body> bodies = {{"models/makehuman_male_cmu.glb", false},
                              {"models/RiggedFigure/RiggedFigure.gltf", false},
                              {"models/corpus/makehuman_female_slim_openpose.glb", false},
                              {"models/corpus/makehuman_female_old_heavy_mixamo.glb", false},
                              {"models/corpus/makehuman_male_old_heavy_unreal.glb", false},
                              {"models/corpus/makehuman_child_mixamo_unity.glb", false},
                              {kMannequinBody, false}};
  if (and_the_male_mirrored)
    bodies.insert(bodies.begin() + 1, {"models/makehuman_male_cmu.glb", true});
  return bodies;
}

inline std::string body_test_name(const Body& body) {
  std::string name =
      std::filesystem::path(body.file).stem().string() + (body.mirror ? "_mirrored" : "");
  std::replace_if(
      name.begin(), name.end(), [](char c) { return !std::isalnum(c); }, '_');
  return name;
}

}  // namespace sweepd::test_models
