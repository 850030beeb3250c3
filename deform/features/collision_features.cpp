#include "deform/features/collision_features.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <thread>

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
      // A relax step can tear the skin too (a fold step eases itself, skin_folding.h).
      const bool torn =
          step == 1 && tears_skin(region, model_.regions.welded_indices, saved_, positions);
      const int now = torn ? pairs : find_pairs(region, positions, detect, report.times);
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

int CollisionFeatures::find_contact_pairs(std::span<const glm::vec3> positions,
                                          const DetectPairs& detect, FeatureTimes& times) {
  const Clock::time_point started = Clock::now();
  const ContactModel& contact = model_.contact;
  if (detect) {
    detect(positions, model_.regions.welded_indices, contact.skin_triangles, contact_pairs_);
  } else {
    const int threads = options_.contact_threads > 0
                            ? options_.contact_threads
                            : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    body_detector_.detect(positions, model_.regions.welded_indices, contact.skin_triangles,
                          contact_pairs_, threads);
  }
  remove_rest_pairs(contact.rest_pairs, contact_pairs_);
  times.detect += Clock::now() - started;
  return static_cast<int>(contact_pairs_.size());
}

int CollisionFeatures::restore_worse_groups(std::span<glm::vec3> positions) {
  // Each vertex holds the groups that moved it, one bit per group (group g: bit g % 64; with
  // more than 64 groups some share a bit and are judged together).
  const std::size_t groups = resolver_.moved_groups();
  groups_of_vertex_.resize(positions.size(), 0);
  for (std::size_t g = 0; g < groups; ++g)
    for (std::uint32_t v : resolver_.moved_group(g))
      groups_of_vertex_[v] |= std::uint64_t{1} << (g % 64);
  const std::span<const std::uint32_t> indices = model_.regions.welded_indices;
  auto count = [&](std::span<const TrianglePair> pairs, std::array<int, 64>& per_bit) {
    per_bit.fill(0);
    for (const TrianglePair& p : pairs) {
      std::uint64_t touched = 0;
      for (std::uint32_t t : {p.first, p.second})
        for (int k = 0; k < 3; ++k) touched |= groups_of_vertex_[indices[3 * t + k]];
      for (int bit = 0; bit < 64; ++bit) per_bit[bit] += (touched >> bit) & 1;
    }
  };
  count(saved_contact_pairs_, group_pairs_before_);
  count(contact_pairs_, group_pairs_after_);
  int restored = 0;
  undone_.assign(groups, 0);
  const auto undo = [&](std::size_t g) {
    for (std::uint32_t v : resolver_.moved_group(g)) positions[v] = saved_body_[v];
    undone_[g] = 1;
    ++restored;
  };
  for (std::size_t g = 0; g < groups; ++g)
    if (group_pairs_after_[g % 64] >= group_pairs_before_[g % 64]) undo(g);
  // Then every group that tore the skin; undoing one can tear the skin at a neighbour's edge,
  // so until none does.
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t g = 0; g < groups; ++g)
      if (!undone_[g] &&
          tears_around(model_.contact, resolver_.moved_group(g), saved_body_, positions)) {
        undo(g);
        changed = true;
      }
  }
  for (std::size_t g = 0; g < groups; ++g)
    for (std::uint32_t v : resolver_.moved_group(g)) groups_of_vertex_[v] = 0;
  return restored;
}

void CollisionFeatures::apply_contact(std::span<glm::vec3> positions, const DetectPairs& detect,
                                      FeatureReport& report) {
  int pairs = find_contact_pairs(positions, detect, report.times);
  report.contact_pairs_before = pairs;
  if (pairs > 0) {
    const Clock::time_point started = Clock::now();
    const std::chrono::nanoseconds detected_before = report.times.detect;
    const std::span<const std::uint32_t> indices = model_.regions.welded_indices;
    volume_before_.resize(sweep_volume_change_.size());
    volume_after_.resize(sweep_volume_change_.size());
    skin_sweep_volumes(model_.contact, indices, positions, volume_before_);
    for (int round = 0; round < options_.contact_rounds && pairs > 0; ++round) {
      saved_body_.assign(positions.begin(), positions.end());
      saved_contact_pairs_ = contact_pairs_;
      // Every group at once; the groups that made their neighbourhood worse undone.
      ContactResult resolved = resolver_.resolve(model_.contact, indices, saved_contact_pairs_,
                                                 options_.contact_gap, positions);
      int now = find_contact_pairs(positions, detect, report.times);
      if (restore_worse_groups(positions) > 0)
        now = find_contact_pairs(positions, detect, report.times);
      if (now < pairs) {
        pairs = now;
        report.contact_moved += resolved.moved;
        report.deepest_contact = std::max(report.deepest_contact, resolved.max_depth);
        continue;
      }
      // Else one group at a time (groups that overlap can spoil each other), each kept only
      // when the pairs drop; the rounds stop when none does.
      std::copy(saved_body_.begin(), saved_body_.end(), positions.begin());
      bool improved = false;
      saved_group_.resize(positions.size());
      for (int g = 0; g < resolved.groups; ++g) {
        std::copy(positions.begin(), positions.end(), saved_group_.begin());
        const ContactResult one = resolver_.resolve(model_.contact, indices, saved_contact_pairs_,
                                                    options_.contact_gap, positions, g);
        if (one.separated == 0) continue;
        if (tears_around(model_.contact, resolver_.moved_group(0), saved_group_, positions)) {
          std::copy(saved_group_.begin(), saved_group_.end(), positions.begin());
          continue;
        }
        now = find_contact_pairs(positions, detect, report.times);
        if (now < pairs) {
          pairs = now;
          improved = true;
          report.contact_moved += one.moved;
          report.deepest_contact = std::max(report.deepest_contact, one.max_depth);
        } else {
          std::copy(saved_group_.begin(), saved_group_.end(), positions.begin());
        }
      }
      // The rounds stop here: trying groups one by one costs a detection each.
      if (!improved) find_contact_pairs(positions, detect, report.times);  // of the kept positions
      break;
    }
    skin_sweep_volumes(model_.contact, indices, positions, volume_after_);
    for (std::size_t s = 0; s < volume_after_.size(); ++s) {
      const double change = volume_after_[s] - volume_before_[s];
      sweep_volume_change_[s] += change;
      report.volume_change += change;
    }
    report.times.contact += Clock::now() - started - (report.times.detect - detected_before);
  }
  report.contact_pairs_after = pairs;
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
  if (options_.contact) apply_contact(positions, detect, report);
  copy_to_seam_copies(model_.regions, positions);
  return report;
}

}  // namespace sweepd::deform
