// CollisionFeatures: the per-frame anatomical features of paper §4.3 on a posed mesh — skin
// folding where a bent joint makes the skin pass through itself, then elbow/knee protrusion
// over the bone proxies — in one call, on the CPU reference or with the pairs found elsewhere
// (gpu::CollisionDetector).
//
// apply
//   Inputs:  skinning   J skinning matrices of the pose
//            detect     optional pair finder with SelfIntersectionDetector::detect's contract;
//                       empty: the CPU reference
//   In/out:  positions  #V posed positions (the sweep poser's output); region vertices move,
//                       UV-seam copies follow their representative
//   Output:  FeatureReport (counts, deepest penetrations, net volume change, the time spent in
//            each stage: detect (the pair finder's calls), fold (fold and relax steps),
//            protrude (the bone proxies)), and
//            sweep_volume_change(): the same change per sweep (CollisionModel::sweep_count
//            values; each region's and each proxy's change goes to the region's limb sweep) —
//            the paper's I_C (§4.4), which DeformJob subtracts from the preserved target.
// Per region with pairs, up to folding_rounds rounds: fold (SkinFolder::fold with the current
// pairs) and detect again; when that does not reduce the pairs, restore and relax
// (SkinFolder::relax) instead; when neither does, restore and stop. So pairs_after never
// exceeds pairs_before, region by region. Then every bone proxy pushes its region's skin out.
// Allocation-free once warm (the detect hook aside). Cost on the shared male bent 150° (CPU,
// bench/collision_bench): about 4× one detect-fold-detect pass, most of it the elbow's rounds.
#pragma once

#include <chrono>
#include <functional>
#include <span>
#include <vector>

#include "deform/features/collision_model.h"
#include "deform/features/self_intersection.h"
#include "deform/features/skin_folding.h"

namespace sweepd::deform {

using DetectPairs =
    std::function<void(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                       std::span<const std::uint32_t> triangles, std::vector<TrianglePair>& pairs)>;

struct CollisionFeatureOptions {
  bool folding = true;
  bool protrusion = true;
  int folding_rounds = 16;       // detect -> fold rounds per region at most
  float folding_gap = 5e-4f;     // m between the two skins of a fold
  float protrusion_gap = 2e-4f;  // m between a proxy and the skin pushed over it
};

// Wall time per stage of CollisionFeatures::apply (steady clock, a few reads per region).
struct FeatureTimes {
  std::chrono::nanoseconds detect{0};    // the pair finder: every region's detection calls
  std::chrono::nanoseconds fold{0};      // fold and relax steps, restores and region volumes
  std::chrono::nanoseconds protrude{0};  // posing the bone proxies and pushing skin out
  FeatureTimes& operator+=(const FeatureTimes& other) {
    detect += other.detect;
    fold += other.fold;
    protrude += other.protrude;
    return *this;
  }
};

struct FeatureReport {
  int pairs_before = 0;  // intersecting pairs over all regions, before folding
  int pairs_after = 0;   // ... after folding (regions that had none are not re-tested)
  int folded = 0;        // vertices pulled back by folding, summed over rounds
  int protruded = 0;     // vertices pushed out by bone proxies
  float deepest_fold = 0.0f, deepest_protrusion = 0.0f;  // m
  double volume_change = 0.0;  // m³, both features together (Σ sweep_volume_change())
  FeatureTimes times{};
};

class CollisionFeatures {
 public:
  // The CollisionModel must outlive this object; this object holds only per-frame scratch.
  explicit CollisionFeatures(const CollisionModel& model,
                             const CollisionFeatureOptions& options = {});

  FeatureReport apply(std::span<const glm::mat4> skinning, std::span<glm::vec3> positions,
                      const DetectPairs& detect = {});
  void set_options(const CollisionFeatureOptions& options) { options_ = options; }
  // Switches folding and protrusion on or off for the next apply calls.
  void select(bool folding, bool protrusion) {
    options_.folding = folding;
    options_.protrusion = protrusion;
  }

  const CollisionRegions& regions() const { return model_.regions; }
  const std::vector<BoneProxy>& proxies() const { return model_.proxies; }
  // Per sweep, the volume the last apply added (m³; negative where folding took it away).
  std::span<const double> sweep_volume_change() const { return sweep_volume_change_; }

 private:
  // Detects the region's pairs into pairs_ (timed into `times`); returns how many.
  int find_pairs(const CollisionRegion& region, std::span<const glm::vec3> positions,
                 const DetectPairs& detect, FeatureTimes& times);
  // Detect -> fold/relax rounds on one region holding `pairs` (in pairs_); returns the pairs
  // left.
  int fold_region(const CollisionRegion& region, int pairs, std::span<glm::vec3> positions,
                  const DetectPairs& detect, FeatureReport& report);

  const CollisionModel& model_;
  CollisionFeatureOptions options_;
  std::vector<double> sweep_volume_change_;
  SelfIntersectionDetector detector_;
  SkinFolder folder_;
  std::vector<TrianglePair> pairs_, saved_pairs_;
  std::vector<glm::vec3> proxy_positions_;
  std::vector<glm::vec3> saved_;  // region positions before a folding round
};

}  // namespace sweepd::deform
