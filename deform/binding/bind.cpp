#include "deform/binding/bind.h"

#include <algorithm>
#include <exception>
#include <optional>
#include <stdexcept>
#include <string>

#include "deform/binding/carried_end.h"
#include "deform/binding/chain_key_ellipses.h"
#include "deform/binding/mesh_parts_joined.h"
#include "deform/binding/rest_sweep.h"
#include "deform/binding/sweep_coordinates.h"
#include "deform/blending/rigid_islands.h"
#include "deform/blending/skinned_share_influences.h"
#include "deform/blending/sweep_blending.h"
#include "deform/mesh/welded_mesh.h"
#include "deform/simd/vertex_blocks.h"
#include "deform/sweep/swept_volume.h"

namespace sweepd::deform {

namespace {

struct SweepPlan {
  BodyPart part;
  std::vector<int> chain;
  glm::vec3 x_hint;
  std::optional<glm::vec3> end;  // where the last joint's bone carries the hand or head
};

// The end a chain's last bone carries (carried_end.h), or none; where none is found, `warnings`
// says so and the part's sweep ends at that joint.
std::optional<glm::vec3> carried_end(const Model& model, const WeldedMesh& mesh,
                                     std::span<const glm::mat4> world_rest, int joint,
                                     CarriedEndKind kind, const std::string& part,
                                     std::vector<std::string>* warnings) {
  const CarriedEnd end = find_carried_end(model, mesh, world_rest, joint, kind);
  if (end.found) return end.point;
  if (warnings)
    warnings->push_back("found no end of the " + part + " on '" + model.skeleton.joints[joint].name +
                        "' (" + end.problem + "): it is skinned by linear blending from that joint on");
  return std::nullopt;
}

// One sweep per part the map has: torso, neck, arms, legs. An absent part is left to skinning,
// and so is a torso of one joint with no neck above it (no link to sweep along: rig_detection
// warns; RigMap::torso_sweep_chain). A neck of one joint (the head's) and the forearm of an arm
// without a hand joint are skinned too (rig_detection warns), unless sweep_carried_ends: then
// they are swept on to the end their bone carries, found on the mesh (carried_end.h), or end at
// that joint where none is found (a warning in `warnings`).
std::vector<SweepPlan> plan_sweeps(const Model& model, const WeldedMesh& mesh, const RigMap& rig,
                                   std::span<const glm::mat4> world_rest, bool sweep_carried_ends,
                                   std::vector<std::string>* warnings) {
  // The body's own axes, so the keys' first axes agree from model to model.
  const BodyAxes axes = rest_body_axes(rig, world_rest);
  std::vector<SweepPlan> plans;
  if (std::vector<int> torso = rig.torso_sweep_chain(); torso.size() >= 2)
    plans.push_back({BodyPart::kTorso, torso, axes.left, std::nullopt});
  if (rig.has_head() && rig.neck.chain.size() >= 2) {
    plans.push_back({BodyPart::kNeck, rig.neck.chain, axes.left, std::nullopt});
  } else if (rig.has_head() && rig.neck.chain.size() == 1 && sweep_carried_ends) {
    if (const auto end = carried_end(model, mesh, world_rest, rig.neck.head, CarriedEndKind::kHead,
                                     "neck", warnings))
      plans.push_back({BodyPart::kNeck, rig.neck.chain, axes.left, end});
  }
  for (const auto& [part, arm] : {std::pair{BodyPart::kLeftArm, &rig.left_arm},
                                  std::pair{BodyPart::kRightArm, &rig.right_arm}}) {
    if (arm->absent()) continue;
    std::vector<int> chain = {arm->upper, arm->lower};
    std::optional<glm::vec3> end;
    if (arm->hand >= 0)
      chain.push_back(arm->hand);
    else if (sweep_carried_ends)
      end = carried_end(model, mesh, world_rest, arm->lower, CarriedEndKind::kHand,
                        std::string(to_string(part)) + "'s forearm", warnings);
    plans.push_back({part, chain, axes.forward, end});
  }
  for (const auto& [part, leg] : {std::pair{BodyPart::kLeftLeg, &rig.left_leg},
                                  std::pair{BodyPart::kRightLeg, &rig.right_leg}})
    if (!leg->absent())
      plans.push_back({part, {leg->upper, leg->lower, leg->foot}, axes.forward, std::nullopt});
  return plans;
}

// The joined vertices of `model` (joined[v] = 1) as a model of their own; body_vertex[b] is the
// model vertex that body vertex b came from. Parts are dropped: the body binds as one mesh.
Model body_of(const Model& model, const std::vector<std::uint8_t>& joined,
              std::vector<std::uint32_t>& body_vertex) {
  Model body;
  body.name = model.name;
  body.skeleton = model.skeleton;
  std::vector<std::uint32_t> body_index(model.vertex_count(), 0);
  for (std::uint32_t v = 0; v < model.vertex_count(); ++v) {
    if (!joined[v]) continue;
    body_index[v] = static_cast<std::uint32_t>(body_vertex.size());
    body_vertex.push_back(v);
    body.positions.push_back(model.positions[v]);
    body.normals.push_back(model.normals[v]);
    if (model.has_uvs()) body.uvs.push_back(model.uvs[v]);
    body.skin_joints.push_back(model.skin_joints[v]);
    body.skin_weights.push_back(model.skin_weights[v]);
  }
  for (std::uint32_t corner : model.indices)  // a triangle lies in one part: all or none joined
    if (joined[corner]) body.indices.push_back(body_index[corner]);
  return body;
}

// One sweep's keys fitted with `choice`, its rest volume measured.
BoundSweep fit_sweep(const WeldedMesh& mesh, std::span<const glm::mat4> world_rest,
                     const SweepPlan& plan, BindOptions options, const SweepChoice& choice) {
  options.intermediate_keys_per_link = choice.keys_per_link;
  BoundSweep sweep = fit_chain_key_ellipses(mesh.positions, mesh.indices, world_rest, plan.part,
                                            plan.chain, plan.end, options, plan.x_hint);
  sweep.choice = choice;
  sweep.rest_volume = sweep_volume(rest_sweep(sweep, options));
  return sweep;
}

BoundModel bind_one_body(const Model& model, const RigMap& rig, const BindOptions& options,
                         const BindProgress& progress, bool sweep_carried_ends);

}  // namespace

// The separate pieces (mesh_parts_joined.h) take no part in the sweeps: the body binds alone,
// and every other vertex follows the model's own skin weights.
BoundModel bind(const Model& model, const RigMap& rig, const BindOptions& options,
                const BindProgress& progress, bool sweep_carried_ends) {
  if (std::string why = model.validate(); !why.empty())
    throw std::invalid_argument("cannot bind an invalid model: " + why);
  const std::vector<std::uint8_t> joined = vertices_joined(model);
  if (std::all_of(joined.begin(), joined.end(), [](std::uint8_t j) { return j != 0; }))
    return bind_one_body(model, rig, options, progress, sweep_carried_ends);
  std::vector<std::uint32_t> body_vertex;
  BoundModel body = bind_one_body(body_of(model, joined, body_vertex), rig, options, progress,
                                  sweep_carried_ends);
  BoundModel bound;
  bound.model = model;
  bound.rig = std::move(body.rig);
  bound.options = body.options;
  bound.sweeps = std::move(body.sweeps);
  bound.edits = std::move(body.edits);
  bound.vertices.assign(model.vertex_count(), VertexBinding{.skin_weight = 1.0f});
  if (!body.skinned_share_joints.empty()) {
    bound.skinned_share_joints = model.skin_joints;
    bound.skinned_share_weights = model.skin_weights;
  }
  for (std::size_t b = 0; b < body_vertex.size(); ++b) {
    bound.vertices[body_vertex[b]] = body.vertices[b];
    if (!body.skinned_share_joints.empty()) {
      bound.skinned_share_joints[body_vertex[b]] = body.skinned_share_joints[b];
      bound.skinned_share_weights[body_vertex[b]] = body.skinned_share_weights[b];
    }
  }
  return bound;
}

namespace {

BoundModel bind_one_body(const Model& model, const RigMap& rig, const BindOptions& options,
                         const BindProgress& progress, bool sweep_carried_ends) {
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

  const std::vector<SweepPlan> plans =
      plan_sweeps(model, mesh, rig, world_rest, sweep_carried_ends, &bound.rig.warnings);
  const SweepChoice choice{.orientation_curve = options.orientation_curve,
                           .keys_per_link = options.intermediate_keys_per_link};
  // Each sweep is fitted alone, so on bind's threads; the first sweep (in order) that cannot be
  // fitted is the error, as one after another would give it.
  bound.sweeps.resize(plans.size());
  std::vector<std::optional<Sweep>> fitted(plans.size());
  std::vector<std::exception_ptr> failed(plans.size());
  run_in_vertex_blocks(plans.size(), kBindThreads, [&](std::size_t begin, std::size_t end) {
    for (std::size_t s = begin; s < end; ++s) {
      if (end == plans.size()) report(0.5 * s / plans.size(), "fitting key ellipses");
      try {
        bound.sweeps[s] = fit_sweep(mesh, world_rest, plans[s], options, choice);
        fitted[s].emplace(rest_sweep(bound.sweeps[s], options));
      } catch (...) {
        failed[s] = std::current_exception();
        return;
      }
    }
  });
  std::vector<Sweep> sweeps;
  for (std::size_t s = 0; s < plans.size(); ++s) {
    if (failed[s]) std::rethrow_exception(failed[s]);
    sweeps.push_back(std::move(*fitted[s]));
  }

  report(0.5, "blending regions");
  bound.vertices = blend_shares(model, mesh, rig, world_rest, bound.sweeps, options);
  // Pieces the model's skinning moves rigidly stay rigid: skinned whole.
  const std::vector<int> rigid = rigid_island_joints(model, mesh);
  for (std::size_t v = 0; v < rigid.size(); ++v)
    if (rigid[v] >= 0) bound.vertices[v] = VertexBinding{.skin_weight = 1.0f};
  SkinInfluences skinned_share =
      skinned_share_influences(model, mesh, bound.vertices, bound.sweeps);
  bound.skinned_share_joints = std::move(skinned_share.joints);
  bound.skinned_share_weights = std::move(skinned_share.weights);

  std::vector<SweepPlanes> planes;
  for (const Sweep& sweep : sweeps)
    planes.push_back(sample_planes(sweep, options.plane_samples_per_span));
  const std::size_t n = model.vertex_count();
  run_in_vertex_blocks(n, kBindThreads, [&](std::size_t begin, std::size_t end) {
    for (std::size_t v = begin; v < end; ++v) {
      // The caller's thread runs the last block: it reports its own progress.
      if (end == n && (v - begin) % 4096 == 0)
        report(0.55 + 0.45 * (v - begin) / (end - begin), "binding vertices");
      VertexBinding& binding = bound.vertices[v];
      for (int k = 0; k < kSweepsPerVertex; ++k)
        if (binding.sweep[k] >= 0)
          binding.coordinate[k] =
              bind_point(sweeps[binding.sweep[k]], planes[binding.sweep[k]], model.positions[v]);
    }
  });
  report(1.0, "done");
  return bound;
}

}  // namespace

SweepRebinder::SweepRebinder(const BoundModel& bound)
    : world_rest_(bound.model.skeleton.world_rest_matrices()) {
  // The body bind fitted the sweeps to (bind: the joined vertices alone).
  const std::vector<std::uint8_t> joined = vertices_joined(bound.model);
  Model body;
  if (!std::all_of(joined.begin(), joined.end(), [](std::uint8_t j) { return j != 0; })) {
    std::vector<std::uint32_t> body_vertex;
    body = body_of(bound.model, joined, body_vertex);
  }
  const Model& fitted = body.positions.empty() ? bound.model : body;
  mesh_ = weld_mesh(fitted.positions, fitted.indices);
  // On the same body, so the carried ends are found where bind found them.
  const bool carried = std::any_of(bound.sweeps.begin(), bound.sweeps.end(),
                                   [](const BoundSweep& s) { return s.ends_on_carried_end(); });
  const std::vector<SweepPlan> plans =
      plan_sweeps(fitted, mesh_, bound.rig, world_rest_, carried, nullptr);
  for (const BoundSweep& sweep : bound.sweeps) {
    const auto plan = std::find_if(plans.begin(), plans.end(),
                                   [&](const SweepPlan& p) { return p.part == sweep.part; });
    x_hints_.push_back(plan == plans.end() ? glm::vec3(1, 0, 0) : plan->x_hint);
    ends_.push_back(plan == plans.end() ? std::nullopt : plan->end);
  }
}

Sweep SweepRebinder::refit(BoundModel& bound, int s, const SweepChoice& choice) {
  const BoundSweep& old = bound.sweeps[s];
  // The keys depend on the key count alone: a choice with the bound sweep's count changes its
  // orientation curve only, and another count is fitted once.
  BoundSweep sweep_fitted;
  if (choice.keys_per_link == old.choice.keys_per_link) {
    sweep_fitted = old;
  } else {
    const std::pair<int, int> key{s, choice.keys_per_link};
    auto fitted = fitted_.find(key);
    if (fitted == fitted_.end())
      fitted = fitted_
                   .emplace(key, fit_sweep(mesh_, world_rest_, {old.part, old.chain, x_hints_[s], ends_[s]},
                                           bound.options, choice))
                   .first;
    sweep_fitted = fitted->second;
  }
  sweep_fitted.choice = choice;
  Sweep sweep = rest_sweep(sweep_fitted, bound.options);
  sweep_fitted.rest_volume = sweep_volume(sweep);
  bound.sweeps[s] = std::move(sweep_fitted);
  return sweep;
}

void SweepRebinder::rebind(BoundModel& bound, int s, const SweepChoice& choice) {
  const Sweep sweep = refit(bound, s, choice);
  const SweepPlanes planes = sample_planes(sweep, bound.options.plane_samples_per_span);
  run_in_vertex_blocks(
      bound.vertices.size(), kBindThreads, [&](std::size_t begin, std::size_t end) {
        for (std::size_t v = begin; v < end; ++v) {
          VertexBinding& binding = bound.vertices[v];
          for (int k = 0; k < kSweepsPerVertex; ++k)
            if (binding.sweep[k] == s)
              binding.coordinate[k] = bind_point(sweep, planes, bound.model.positions[v]);
        }
      });
}

void SweepRebinder::rebind_vertices(BoundModel& bound, int s, const SweepChoice& choice,
                                    std::span<const std::uint32_t> vertices) {
  const Sweep sweep = refit(bound, s, choice);
  const SweepPlanes planes = sample_planes(sweep, bound.options.plane_samples_per_span);
  for (const std::uint32_t v : vertices) {
    VertexBinding& binding = bound.vertices[v];
    for (int k = 0; k < kSweepsPerVertex; ++k)
      if (binding.sweep[k] == s)
        binding.coordinate[k] = bind_point(sweep, planes, bound.model.positions[v]);
  }
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
