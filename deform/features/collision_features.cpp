#include "deform/features/collision_features.h"

#include <algorithm>
#include <chrono>

#include "deform/mesh/enclosed_volume.h"

namespace sweepd::deform {
namespace {

using Clock = std::chrono::steady_clock;

}  // namespace

CollisionFeatures::CollisionFeatures(const CollisionModel& model,
                                     const CollisionFeatureOptions& options)
    : model_(model), options_(options), sweep_volume_change_(model.sweep_count, 0.0) {}

int CollisionFeatures::find_pairs(const CollisionRegion& region,
                                  std::span<const glm::vec3> positions, const DetectPairs& detect,
                                  FeatureTimes& times) {
  const Clock::time_point started = Clock::now();
  if (detect) {
    detect(positions, model_.regions.welded_indices, region.triangles, pairs_);
  } else {
    detector_.detect(positions, model_.regions.welded_indices, region.triangles, pairs_);
  }
  times.detect += Clock::now() - started;
  return static_cast<int>(pairs_.size());
}

int CollisionFeatures::fold_region(const CollisionRegion& region, int pairs,
                                   std::span<glm::vec3> positions, const DetectPairs& detect,
                                   FeatureReport& report) {
  for (int round = 0; round < options_.folding_rounds && pairs > 0; ++round) {
    for (std::size_t i = 0; i < region.vertices.size(); ++i)
      saved_[i] = positions[region.vertices[i]];
    saved_pairs_ = pairs_;
    bool reduced = false;
    // A fold step; when it does not reduce the pairs, a relax step instead; else stop.
    for (int step = 0; step < 2 && !reduced; ++step) {
      FoldingResult folded;
      if (step == 0) {
        folded = folder_.fold(region, model_.regions.welded_indices, saved_pairs_,
                              options_.folding_gap, positions);
      } else {
        folder_.relax(region, model_.regions.welded_indices, saved_pairs_, positions);
      }
      const int now = find_pairs(region, positions, detect, report.times);
      reduced = now < pairs;
      if (!reduced) {  // never keep a step that does not help
        for (std::size_t i = 0; i < region.vertices.size(); ++i)
          positions[region.vertices[i]] = saved_[i];
        continue;
      }
      pairs = now;
      report.folded += folded.moved;
      report.deepest_fold = std::max(report.deepest_fold, folded.max_depth);
    }
    if (!reduced) break;
  }
  return pairs;
}

FeatureReport CollisionFeatures::apply(std::span<const glm::mat4> skinning,
                                       std::span<glm::vec3> positions, const DetectPairs& detect) {
  FeatureReport report;
  std::fill(sweep_volume_change_.begin(), sweep_volume_change_.end(), 0.0);
  if (options_.folding) {
    for (const CollisionRegion& region : model_.regions.regions) {
      const int before = find_pairs(region, positions, detect, report.times);
      report.pairs_before += before;
      if (before == 0) continue;
      const Clock::time_point started = Clock::now();
      const std::chrono::nanoseconds detected_before = report.times.detect;
      saved_.resize(region.vertices.size());
      const double volume_before =
          enclosed_volume(positions, model_.regions.welded_indices, region.triangles);
      report.pairs_after += fold_region(region, before, positions, detect, report);
      const double change =
          enclosed_volume(positions, model_.regions.welded_indices, region.triangles) -
          volume_before;
      report.volume_change += change;
      if (region.sweep >= 0) sweep_volume_change_[region.sweep] += change;
      // The region's folding time, less the detection calls it made.
      report.times.fold += Clock::now() - started - (report.times.detect - detected_before);
    }
  }
  if (options_.protrusion) {
    const Clock::time_point started = Clock::now();
    for (const BoneProxy& proxy : model_.proxies) {
      proxy_positions_.resize(proxy.rest_positions.size());
      const glm::vec3 anchor = pose_bone_proxy(proxy, skinning, proxy_positions_);
      const ProtrusionResult pushed = push_out_of_bone_proxy(
          proxy_positions_, proxy.indices, anchor, model_.regions.regions[proxy.region],
          model_.regions.welded_indices, options_.protrusion_gap, positions);
      report.protruded += pushed.moved;
      report.deepest_protrusion = std::max(report.deepest_protrusion, pushed.max_depth);
      report.volume_change += pushed.volume_change;
      if (const int s = model_.regions.regions[proxy.region].sweep; s >= 0)
        sweep_volume_change_[s] += pushed.volume_change;
    }
    report.times.protrude += Clock::now() - started;
  }
  copy_to_seam_copies(model_.regions, positions);
  return report;
}

}  // namespace sweepd::deform
