#include "gpu/sheet/deform_with.h"

#include <algorithm>

namespace sweepd::sheet {

bool uses_collision(std::span<const deform::MethodChoice> methods) {
  return std::any_of(methods.begin(), methods.end(),
                     [](const deform::MethodChoice& m) { return m.collision; });
}

const deform::SweepPoser& deform_with(const deform::MethodChoice& m,
                                      const deform::ModelRuntime& runtime,
                                      deform::DeformContext& context, PairSource* pairs,
                                      deform::Pose pose, std::span<glm::vec3> positions) {
  deform::DeformJob job{.runtime = runtime,
                        .pose = pose,
                        .method = m.method,
                        .features = {.folding = m.collision,
                                     .protrusion = m.collision,
                                     .volume = m.preserve_volume,
                                     .contact = m.contact},
                        .positions = positions};
  if (m.collision && pairs != nullptr) job.options.detect = pairs->begin();
  const deform::DeformReport report = job.run(context);
  if (m.collision && pairs != nullptr) pairs->finish(report.features);
  if (m.method != deform::DeformMethod::kSweep)
    context.sweep_poser().set_pose(context.world_pose());  // section planes
  return context.sweep_poser();
}

}  // namespace sweepd::sheet
