#include "deform/collision_features.h"

#include <algorithm>

namespace sweepd::deform {

CollisionFeatures::CollisionFeatures(const BoundModel& bound,
                                     const CollisionFeatureOptions& options)
    : options_(options),
      regions_(find_collision_regions(bound, options.regions)),
      proxies_(make_bone_proxies(bound, regions_, options.proxies)) {}

FeatureReport CollisionFeatures::apply(std::span<const glm::mat4> skinning,
                                       std::span<glm::vec3> positions, const DetectPairs& detect) {
  FeatureReport report;
  auto find_pairs = [&](const CollisionRegion& region) {
    if (detect) {
      detect(positions, regions_.welded_indices, region.triangles, pairs_);
    } else {
      detector_.detect(positions, regions_.welded_indices, region.triangles, pairs_);
    }
    return static_cast<int>(pairs_.size());
  };
  if (options_.folding) {
    for (const CollisionRegion& region : regions_.regions) {
      const int before = find_pairs(region);
      report.pairs_before += before;
      if (before == 0) continue;
      const FoldingResult folded =
          folder_.fold(region, regions_.welded_indices, pairs_, options_.folding_gap, positions);
      report.folded += folded.moved;
      report.deepest_fold = std::max(report.deepest_fold, folded.max_depth);
      report.volume_change += folded.volume_change;
      report.pairs_after += find_pairs(region);
    }
  }
  if (options_.protrusion) {
    for (const BoneProxy& proxy : proxies_) {
      proxy_positions_.resize(proxy.rest_positions.size());
      const glm::vec3 anchor = pose_bone_proxy(proxy, skinning, proxy_positions_);
      const ProtrusionResult pushed = push_out_of_bone_proxy(
          proxy_positions_, proxy.indices, anchor, regions_.regions[proxy.region],
          regions_.welded_indices, options_.protrusion_gap, positions);
      report.protruded += pushed.moved;
      report.deepest_protrusion = std::max(report.deepest_protrusion, pushed.max_depth);
      report.volume_change += pushed.volume_change;
    }
  }
  copy_to_seam_copies(regions_, positions);
  return report;
}

}  // namespace sweepd::deform
