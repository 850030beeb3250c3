// Colours that show a binding: one per sweep (torso, neck, arms, legs), mixed by each vertex's
// shares; grey for the share that follows the model's own skinning. Used by `bind --debug-gltf`
// and `render --segments`.
#pragma once

#include <glm/glm.hpp>
#include <vector>

#include "deform/binding/bound_model.h"

namespace sweepd::cli {

std::vector<glm::vec3> segment_colours(const deform::BoundModel& bound);

}  // namespace sweepd::cli
