// Each body a test checks, as is, mirrored (tests/mirrored_model.h) and rescaled
// (tests/rescaled_model.h), so that a figure tuned to one body, one side or one size shows.
// Input: named models. Output: per model, in this order, the model, its mirrored copy
// ("NAME mirrored") and a copy at `scale` ("NAME xSCALE"), each with the scale it was made at.
#pragma once

#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "deform/model/model.h"
#include "tests/mirrored_model.h"
#include "tests/rescaled_model.h"

namespace sweepd::test_models {

struct BodyVariant {
  std::string name;
  deform::Model model;
  float scale = 1.0f;
};

// Variants per body: the plain one is variants[3 * i], its mirror and rescaled copy follow.
constexpr int kVariantsPerBody = 3;

inline std::vector<BodyVariant> plain_mirrored_and_rescaled(
    const std::vector<std::pair<std::string, const deform::Model*>>& bodies, float scale) {
  std::vector<BodyVariant> variants;
  char suffix[32];
  std::snprintf(suffix, sizeof suffix, " x%g", scale);
  for (const auto& [name, model] : bodies) {
    variants.push_back({name, *model});
    variants.push_back({name + " mirrored", mirrored(*model)});
    variants.push_back({name + suffix, rescaled(*model, scale), scale});
  }
  return variants;
}

}  // namespace sweepd::test_models
