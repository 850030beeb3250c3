// A model scaled about the origin (its rest mesh and its skeleton's offsets): the same body at
// another size, for tests that check nothing is tuned to one body's size.
#pragma once

#include "deform/model/model.h"

namespace sweepd::test_models {

inline deform::Model rescaled(deform::Model model, float scale) {
  for (glm::vec3& p : model.positions) p *= scale;
  for (deform::Joint& joint : model.skeleton.joints) joint.rest_translation *= scale;
  return model;
}

}  // namespace sweepd::test_models
