#include "deform/features/collision_model.h"

namespace sweepd::deform {

CollisionModel make_collision_model(const BoundModel& bound, const CollisionRegionOptions& regions,
                                    const BoneProxyOptions& proxies) {
  CollisionModel model;
  model.regions = find_collision_regions(bound, regions);
  model.proxies = make_bone_proxies(bound, model.regions, proxies);
  model.contact = make_contact_model(bound, model.regions.welded_indices);
  model.sweep_count = static_cast<int>(bound.sweeps.size());
  return model;
}

}  // namespace sweepd::deform
