// AnatomicalFeatures: the features a caller selects on top of the sweep deformation (paper
// §4.3–4.4) — skin folding, bone protrusion, volume preservation, muscle bulge — and
// FeatureApplier, which applies a selection to frames of one bound model. sweepctl
// (cli/posed_model.cpp) and the daemon (server/pose_request.cpp) both pose through it, so
// the same selection gives the same vertices bit for bit.
//
// FeatureApplier::select(features, deformer): sets the deformer's volume/bulge options
//   (keeping its others) and arms folding/protrusion; the collision regions and bone proxies
//   are built on the first selection that needs them (once per applier).
// FeatureApplier::apply(deformer, positions, normals): after deformer.deform(...) with the
//   sweep method: folding then protrusion on `positions` (#V); when a vertex moved and
//   `normals` is not empty (#V), the normals are recomputed (area-weighted, UV-seam copies
//   sharing one, like the sweep poser's). Returns what folding and protrusion did (zeros when
//   neither is selected). Allocation-free once warm.
// The BoundModel must outlive the applier.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "deform/features/collision_features.h"
#include "deform/job/deformer.h"

namespace sweepd::deform {

struct AnatomicalFeatures {
  bool folding = false, protrusion = false, volume = false, bulge = false;
  bool any() const { return folding || protrusion || volume || bulge; }
  // Folding or protrusion: what FeatureApplier::apply does after the deformation.
  bool collision() const { return folding || protrusion; }
  bool operator==(const AnatomicalFeatures&) const = default;
};

// "folding,protrusion" style list of the selected features ("" when none).
std::string to_string(const AnatomicalFeatures& features);

class FeatureApplier {
 public:
  explicit FeatureApplier(const BoundModel& bound) : bound_(bound) {}

  void select(const AnatomicalFeatures& features, Deformer& deformer);
  FeatureReport apply(const Deformer& deformer, std::span<glm::vec3> positions,
                      std::span<glm::vec3> normals);

 private:
  const BoundModel& bound_;
  AnatomicalFeatures selected_;
  std::unique_ptr<CollisionFeatures> collision_;
  std::vector<glm::vec3> welded_normals_;
};

}  // namespace sweepd::deform
