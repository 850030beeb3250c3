#include "deform/job/model_runtime.h"

#include <atomic>
#include <stdexcept>
#include <string>

#include "deform/model/forward_kinematics.h"
#include "deform/volume/volume_preservation.h"

namespace sweepd::deform {

namespace {

std::uint64_t next_serial() {
  static std::atomic<std::uint64_t> serial{0};
  return ++serial;
}

KeyEllipseEdits validated(KeyEllipseEdits edits, const BoundModel& bound) {
  if (std::string why = validate(edits, bound); !why.empty())
    throw std::invalid_argument("key ellipse edits: " + why);
  return edits;
}

}  // namespace

ModelRuntime::ModelRuntime(const BoundModel& bound, const CollisionRegionOptions& regions,
                           const BoneProxyOptions& proxies)
    : bound_(bound),
      edits_(validated(bound.edits, bound)),
      poser_tables_(make_sweep_poser_tables(bound)),
      rest_volumes_(rest_sweep_volumes(bound)),
      collision_(make_collision_model(bound, regions, proxies)),
      world_rest_inverse_(world_rest_inverse_matrices(bound.model.skeleton)),
      skinning_table_(bound.model),
      serial_(next_serial()) {}

}  // namespace sweepd::deform
