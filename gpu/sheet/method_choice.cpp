#include "gpu/sheet/method_choice.h"

#include <algorithm>

namespace sweepd::sheet {

const std::map<std::string, MethodChoice>& methods_by_name() {
  static const std::map<std::string, MethodChoice> methods = {
      {"sweep", {"sweep", deform::DeformMethod::kSweep, false}},
      {"sweep+volume", {"sweep+volume", deform::DeformMethod::kSweep, true}},
      {"sweep+features", {"sweep+features", deform::DeformMethod::kSweep, false, true}},
      {"sweep+contact", {"sweep+contact", deform::DeformMethod::kSweep, false, true, true}},
      {"lbs", {"lbs", deform::DeformMethod::kLbs, false}},
      {"dqs", {"dqs", deform::DeformMethod::kDqs, false}}};
  return methods;
}

bool uses_collision(std::span<const MethodChoice> methods) {
  return std::any_of(methods.begin(), methods.end(),
                     [](const MethodChoice& m) { return m.collision; });
}

const deform::SweepPoser& deform_with(const MethodChoice& m, const deform::ModelRuntime& runtime,
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
