// CollisionFeatures: the per-frame anatomical features of paper §4.3 on a posed mesh — skin
// folding where a bent joint makes the skin pass through itself, then elbow/knee protrusion
// over the bone proxies, then whole-body contact (skin_contact.h, beyond the paper) — in one call,
// on the CPU reference or with the pairs found elsewhere (gpu::CollisionDetector).
//
// apply
//   Inputs:  skinning   J skinning matrices of the pose
//            detect     optional pair finder with SelfIntersectionDetector::detect's contract;
//                       empty: the CPU reference (regions: SelfIntersectionDetector; contact:
//                       WholeBodyDetector on contact_threads). Contact passes the whole skin
//                       (CollisionModel::contact.skin_triangles) through the same hook.
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
// Then contact: the whole skin's pairs less the rest pose's (contact_pairs_before); up to
// contact_rounds rounds of ContactResolver::resolve (every group) and detect again; the groups
// whose neighbourhood (pairs touching their moved vertices) did not lose pairs are restored and
// the pairs detected again; the round is kept when the pairs dropped. Else it is undone and
// each group is tried alone, kept only when the pairs drop (one detection per group), and the
// rounds stop. So contact_pairs_after <= before, frame by frame. Its volume
// change goes to I_C per sweep by skin_sweep_volumes (each triangle's sweep).
// Allocation-free once warm (the detect hook aside). Cost on the shared male bent 150° (CPU,
// bench/collision_bench): about 4× one detect-fold-detect pass, most of it the elbow's rounds.
#pragma once

#include <array>
#include <chrono>
#include <functional>
#include <span>
#include <vector>

#include "deform/features/collision_model.h"
#include "deform/features/self_intersection.h"
#include "deform/features/skin_contact.h"
#include "deform/features/skin_folding.h"
#include "deform/features/whole_body_detector.h"

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
  bool contact = false;          // whole-body contact (skin_contact.h)
  int contact_rounds = 4;        // resolve -> detect rounds at most
  float contact_gap = 5e-4f;     // m between two skins in contact
  int contact_threads = 0;       // the CPU detector's threads; 0: every hardware thread
};

// Wall time per stage of CollisionFeatures::apply (steady clock, a few reads per region).
struct FeatureTimes {
  std::chrono::nanoseconds detect{0};    // the pair finder: every region's detection calls
  std::chrono::nanoseconds fold{0};      // fold and relax steps, restores and region volumes
  std::chrono::nanoseconds protrude{0};  // posing the bone proxies and pushing skin out
  std::chrono::nanoseconds contact{0};   // contact's resolve steps, restores and volumes
  FeatureTimes& operator+=(const FeatureTimes& other) {
    detect += other.detect;
    fold += other.fold;
    protrude += other.protrude;
    contact += other.contact;
    return *this;
  }
};

struct FeatureReport {
  int pairs_before = 0;          // intersecting pairs over all regions, before folding
  int pairs_after = 0;           // ... after folding (regions that had none are not re-tested)
  int folded = 0;                // vertices pulled back by folding, summed over rounds
  int protruded = 0;             // vertices pushed out by bone proxies
  int contact_pairs_before = 0;  // whole-skin pairs (less the rest pose's), before contact
  int contact_pairs_after = 0;   // ... after contact's rounds
  int contact_moved = 0;         // vertices pulled back by contact, summed over rounds
  float deepest_contact = 0.0f;  // m
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
  // Switches folding, protrusion and contact on or off for the next apply calls.
  void select(bool folding, bool protrusion, bool contact = false) {
    options_.folding = folding;
    options_.protrusion = protrusion;
    options_.contact = contact;
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
  // The whole skin's pairs less the rest pose's into contact_pairs_; returns how many.
  int find_contact_pairs(std::span<const glm::vec3> positions, const DetectPairs& detect,
                         FeatureTimes& times);
  void apply_contact(std::span<glm::vec3> positions, const DetectPairs& detect,
                     FeatureReport& report);
  // After a resolve step: restores the vertices of every group whose neighbourhood holds no
  // fewer pairs than before the step (pairs touching its moved vertices); returns how many.
  int restore_worse_groups(std::span<glm::vec3> positions);

  const CollisionModel& model_;
  CollisionFeatureOptions options_;
  std::vector<double> sweep_volume_change_;
  SelfIntersectionDetector detector_;
  SkinFolder folder_;
  std::vector<TrianglePair> pairs_, saved_pairs_;
  std::vector<glm::vec3> proxy_positions_;
  std::vector<glm::vec3> saved_;  // region positions before a folding round
  WholeBodyDetector body_detector_;
  ContactResolver resolver_;
  std::vector<TrianglePair> contact_pairs_, saved_contact_pairs_;
  std::vector<glm::vec3> saved_body_;                 // every position before a contact round
  std::vector<glm::vec3> saved_group_;                // every position before one group's step
  std::vector<double> volume_before_, volume_after_;  // per sweep, of the skin
  std::vector<std::uint64_t> groups_of_vertex_;       // per vertex: the moved groups, one bit each
  std::vector<std::uint8_t> undone_;                  // per moved group: restored
  std::array<int, 64> group_pairs_before_{}, group_pairs_after_{};
};

}  // namespace sweepd::deform
