#include "cli/segment_colours.h"

namespace sweepd::cli {

std::vector<glm::vec3> segment_colours(const deform::BoundModel& bound) {
  static const glm::vec3 sweep_colours[] = {{0.85f, 0.45f, 0.35f}, {0.9f, 0.8f, 0.3f},
                                            {0.35f, 0.6f, 0.9f},   {0.35f, 0.85f, 0.8f},
                                            {0.55f, 0.8f, 0.35f},  {0.75f, 0.5f, 0.85f}};
  std::vector<glm::vec3> colours;
  colours.reserve(bound.vertices.size());
  for (const deform::VertexBinding& b : bound.vertices) {
    glm::vec3 c = b.skin_weight * glm::vec3(0.6f);
    for (int k = 0; k < deform::kSweepsPerVertex; ++k)
      if (b.sweep[k] >= 0) c += b.weight[k] * sweep_colours[b.sweep[k] % 6];
    colours.push_back(c);
  }
  return colours;
}

}  // namespace sweepd::cli
