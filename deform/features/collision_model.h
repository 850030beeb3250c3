// CollisionModel: what the anatomical features of paper §4.3 need of a bound model that never
// changes — the collision regions (collision_regions.h), the bone proxies over them
// (bone_proxy.h) and the whole-body contact model (skin_contact.h: the skin triangles, the
// rest pose's own intersecting pairs, the skin's adjacency). Built once per model
// (make_collision_model) and shared read-only by every CollisionFeatures of that model, on any
// thread.
// Inputs:  bound    the BoundModel
//          regions  window sizes; proxies: proxy sizes
// Output:  regions (up to 8), proxies (one per elbow/knee region), contact, sweep_count =
//          bound.sweeps.size() (the length of a per-sweep volume change)
#pragma once

#include <vector>

#include "deform/binding/bound_model.h"
#include "deform/features/bone_proxy.h"
#include "deform/features/collision_regions.h"
#include "deform/features/skin_contact.h"

namespace sweepd::deform {

struct CollisionModel {
  CollisionRegions regions;
  std::vector<BoneProxy> proxies;
  ContactModel contact;
  int sweep_count = 0;
};

CollisionModel make_collision_model(const BoundModel& bound,
                                    const CollisionRegionOptions& regions = {},
                                    const BoneProxyOptions& proxies = {});

}  // namespace sweepd::deform
