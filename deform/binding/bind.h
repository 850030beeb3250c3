// bind: binds a rigged Model to its control sweep surfaces (paper §3) — the key ellipses of the
// torso, neck, arm and leg sweeps, the blend shares of every vertex, and each vertex's sweep
// coordinates. Run once per model (the server keeps the result in .sweepbind files).
//
// Inputs:  model (passes Model::validate), rig (detect_rig_map or a JSON override), options,
//          progress (optional): called with a fraction in [0, 1] and the stage's name.
// Output:  BoundModel; every vertex has finite coordinates, and rest_positions_from_binding
//          reconstructs the rest mesh (up to float rounding).
// Throws std::invalid_argument naming the problem (invalid model or rig, a sweep that cannot
// be fitted).
#pragma once

#include <functional>
#include <glm/glm.hpp>
#include <map>
#include <optional>
#include <span>
#include <string_view>
#include <utility>
#include <vector>

#include "deform/binding/bind_threads.h"
#include "deform/binding/bound_model.h"
#include "deform/mesh/welded_mesh.h"
#include "deform/model/model.h"
#include "deform/rig/rig_map.h"
#include "deform/sweep/sweep.h"

namespace sweepd::deform {

using BindProgress = std::function<void(double fraction, std::string_view stage)>;

// sweep_carried_ends: sweep a neck of one joint (the head's) and the forearm of an arm without a
// hand joint on to the end their bone carries, found on the mesh (carried_end.h; the end then
// skinned, rigid with the bone), instead of skinning them. Off by default: on the corpus's
// OpenPose body it left the sweep worse than skinning in more (frame, region) pairs of the
// corpus gate (96 -> 108 with the forearms alone, 176 with the neck too; docs/carried_ends.md).
BoundModel bind(const Model& model, const RigMap& rig, const BindOptions& options = {},
                const BindProgress& progress = {}, bool sweep_carried_ends = false);

// SweepRebinder: fits one sweep of a bound model again with another SweepChoice (its keys per
// link, its orientation curve) and binds again the coordinates of the vertices on it; the
// blend shares, the other sweeps and everything else stay. What the binding's self-check tries
// where a sweep loses to skinning. Built once per bound model (it welds the body's mesh, as
// bind does, and finds again the ends its sweeps run on to, if any); rebind throws std::invalid_argument as bind does when the sweep cannot be fitted.
// The key ellipses depend on the key count alone: a choice with the sweep's own count keeps its
// keys (only the orientation curve changes), and each other count is fitted once per sweep and
// kept for the next choice with it.
class SweepRebinder {
 public:
  explicit SweepRebinder(const BoundModel& bound);
  void rebind(BoundModel& bound, int sweep, const SweepChoice& choice);
  // The same fit, binding again only `vertices` (model indices; those on the sweep get the
  // coordinates rebind gives them, the sweep's others keep their old ones): what the self-check
  // judges a candidate's few likeliest losing edges on before binding it whole.
  void rebind_vertices(BoundModel& bound, int sweep, const SweepChoice& choice,
                       std::span<const std::uint32_t> vertices);

 private:
  WeldedMesh mesh_;
  std::map<std::pair<int, int>, BoundSweep> fitted_;  // (sweep, keys per link): its fit
  std::vector<glm::mat4> world_rest_;
  std::vector<glm::vec3> x_hints_;  // per sweep: its first key's first axis hint
  std::vector<std::optional<glm::vec3>> ends_;  // per sweep: the end its last bone carries
  // Sets bound.sweeps[sweep] to its fit with `choice` and returns that sweep at rest.
  Sweep refit(BoundModel& bound, int sweep, const SweepChoice& choice);
};

// Every vertex evaluated from its binding at the rest pose (skinned share: the rest position).
std::vector<glm::vec3> rest_positions_from_binding(const BoundModel& bound);

}  // namespace sweepd::deform
