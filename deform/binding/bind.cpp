#include "deform/binding/bind.h"

#include <stdexcept>

#include "deform/binding/chain_key_ellipses.h"
#include "deform/binding/rest_sweep.h"
#include "deform/binding/sweep_coordinates.h"
#include "deform/blending/skinned_share_influences.h"
#include "deform/blending/sweep_blending.h"
#include "deform/mesh/welded_mesh.h"
#include "deform/sweep/swept_volume.h"

namespace sweepd::deform {

namespace {

struct SweepPlan {
  BodyPart part;
  std::vector<int> chain;
  glm::vec3 x_hint;
};

// One sweep per part the map has: torso, neck, arms, legs (an absent part is left to skinning).
std::vector<SweepPlan> plan_sweeps(const RigMap& rig, std::span<const glm::mat4> world_rest) {
  // The body's own axes, so the keys' first axes agree from model to model.
  const BodyAxes axes = rest_body_axes(rig, world_rest);
  std::vector<SweepPlan> plans = {{BodyPart::kTorso, rig.torso.chain, axes.left}};
  if (rig.has_head()) plans.push_back({BodyPart::kNeck, rig.neck.chain, axes.left});
  for (const auto& [part, arm] : {std::pair{BodyPart::kLeftArm, &rig.left_arm},
                                  std::pair{BodyPart::kRightArm, &rig.right_arm}})
    if (!arm->absent()) plans.push_back({part, {arm->upper, arm->lower, arm->hand}, axes.forward});
  for (const auto& [part, leg] : {std::pair{BodyPart::kLeftLeg, &rig.left_leg},
                                  std::pair{BodyPart::kRightLeg, &rig.right_leg}})
    if (!leg->absent()) plans.push_back({part, {leg->upper, leg->lower, leg->foot}, axes.forward});
  return plans;
}

}  // namespace

BoundModel bind(const Model& model, const RigMap& rig, const BindOptions& options,
                const BindProgress& progress) {
  if (std::string why = model.validate(); !why.empty())
    throw std::invalid_argument("cannot bind an invalid model: " + why);
  if (std::string why = validate_rig_map(rig, model.skeleton); !why.empty())
    throw std::invalid_argument("cannot bind with this rig map: " + why);
  if (options.intermediate_keys_per_link < 0 || options.plane_samples_per_span < 1 ||
      !(options.transition_half_width > 0.0f) || !(options.end_blend_half_width > 0.0f))
    throw std::invalid_argument("bind options out of range");
  auto report = [&](double fraction, std::string_view stage) {
    if (progress) progress(fraction, stage);
  };

  BoundModel bound;
  bound.model = model;
  bound.rig = rig;
  bound.options = options;
  const std::vector<glm::mat4> world_rest = model.skeleton.world_rest_matrices();

  // Cross-section loops are chained through shared vertices, and the blending walks the
  // surface: weld the UV-seam copies once, for every stage.
  const WeldedMesh mesh = weld_mesh(model.positions, model.indices);

  const std::vector<SweepPlan> plans = plan_sweeps(rig, world_rest);
  std::vector<Sweep> sweeps;
  for (std::size_t s = 0; s < plans.size(); ++s) {
    report(0.5 * s / plans.size(), "fitting key ellipses");
    BoundSweep sweep =
        fit_chain_key_ellipses(mesh.positions, mesh.indices, world_rest, plans[s].part,
                               plans[s].chain, options, plans[s].x_hint);
    sweeps.push_back(rest_sweep(sweep, options));
    sweep.rest_volume = sweep_volume(sweeps.back());
    bound.sweeps.push_back(std::move(sweep));
  }

  report(0.5, "blending regions");
  bound.vertices = blend_shares(model, mesh, rig, world_rest, bound.sweeps, options);
  SkinInfluences skinned_share =
      skinned_share_influences(model, mesh, bound.vertices, bound.sweeps);
  bound.skinned_share_joints = std::move(skinned_share.joints);
  bound.skinned_share_weights = std::move(skinned_share.weights);

  std::vector<SweepPlanes> planes;
  for (const Sweep& sweep : sweeps)
    planes.push_back(sample_planes(sweep, options.plane_samples_per_span));
  const std::size_t n = model.vertex_count();
  for (std::size_t v = 0; v < n; ++v) {
    if (v % 4096 == 0) report(0.55 + 0.45 * v / n, "binding vertices");
    VertexBinding& binding = bound.vertices[v];
    for (int k = 0; k < kSweepsPerVertex; ++k)
      if (binding.sweep[k] >= 0)
        binding.coordinate[k] =
            bind_point(sweeps[binding.sweep[k]], planes[binding.sweep[k]], model.positions[v]);
  }
  report(1.0, "done");
  return bound;
}

std::vector<glm::vec3> rest_positions_from_binding(const BoundModel& bound) {
  std::vector<Sweep> sweeps;
  for (const BoundSweep& sweep : bound.sweeps) sweeps.push_back(rest_sweep(sweep, bound.options));
  std::vector<glm::vec3> positions(bound.vertices.size());
  for (std::size_t v = 0; v < positions.size(); ++v) {
    const VertexBinding& binding = bound.vertices[v];
    glm::vec3 p = binding.skin_weight * bound.model.positions[v];
    for (int k = 0; k < kSweepsPerVertex; ++k)
      if (binding.sweep[k] >= 0)
        p += binding.weight[k] * evaluate_point(sweeps[binding.sweep[k]], binding.coordinate[k]);
    positions[v] = p;
  }
  return positions;
}

}  // namespace sweepd::deform
