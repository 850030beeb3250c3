#include "deform/blending/skinned_share_influences.h"

#include <algorithm>
#include <numeric>

#include "deform/mesh/length_weighted_smoothing.h"

namespace sweepd::deform {

namespace {

// Bound to an arm sweep and to the torso sweep, with a skinned share.
bool in_shoulder_ring(const VertexBinding& binding, std::span<const BoundSweep> sweeps) {
  if (binding.skin_weight <= 0.0f) return false;
  bool arm = false, torso = false;
  for (int k = 0; k < kSweepsPerVertex; ++k) {
    if (binding.sweep[k] < 0 || binding.weight[k] <= 0.0f) continue;
    const BodyPart part = sweeps[binding.sweep[k]].part;
    arm |= part == BodyPart::kLeftArm || part == BodyPart::kRightArm;
    torso |= part == BodyPart::kTorso;
  }
  return arm && torso;
}

}  // namespace

SkinInfluences skinned_share_influences(const Model& model, const WeldedMesh& mesh,
                                        std::span<const VertexBinding> bindings,
                                        std::span<const BoundSweep> sweeps) {
  SkinInfluences result{model.skin_joints, model.skin_weights};
  const std::size_t welded_count = mesh.vertex_count();
  const std::vector<std::uint32_t>& welded = mesh.welded_id;
  // Per welded vertex: one model vertex standing for it, and whether it is smoothed.
  constexpr std::uint32_t kNone = ~0u;
  std::vector<std::uint32_t> model_vertex(welded_count, kNone);
  std::vector<bool> ring(welded_count, false);
  for (std::size_t v = 0; v < welded.size(); ++v) {
    if (model_vertex[welded[v]] == kNone) model_vertex[welded[v]] = static_cast<std::uint32_t>(v);
    if (in_shoulder_ring(bindings[v], sweeps)) ring[welded[v]] = true;
  }
  if (std::none_of(ring.begin(), ring.end(), [](bool r) { return r; })) return result;

  // Dense weight rows for the ring and its border (the rows the passes read), by row index.
  const int joints = model.skeleton.size();
  std::vector<std::uint32_t> row_of(welded_count, kNone);
  std::vector<std::uint32_t> ring_vertices;
  std::size_t rows = 0;
  auto add_row = [&](std::uint32_t w) {
    if (row_of[w] == kNone) row_of[w] = static_cast<std::uint32_t>(rows++);
  };
  for (std::uint32_t w = 0; w < welded_count; ++w) {
    if (!ring[w]) continue;
    ring_vertices.push_back(w);
    add_row(w);
    for (std::uint32_t u : mesh.adjacency.neighbours(w)) add_row(u);
  }
  std::vector<float> weights(rows * joints, 0.0f);
  for (std::uint32_t w = 0; w < welded_count; ++w) {
    if (row_of[w] == kNone) continue;
    const std::uint32_t v = model_vertex[w];
    for (int k = 0; k < kInfluences; ++k)
      weights[row_of[w] * joints + model.skin_joints[v][k]] += model.skin_weights[v][k];
  }
  LengthWeightedSmoothing smoothing;
  for (std::uint32_t w : ring_vertices)
    smoothing.add(row_of[w], mesh.adjacency.neighbours(w), mesh.adjacency.lengths(w),
                  [&](std::uint32_t u) { return row_of[u]; });
  smoothing.smooth(joints, kShoulderSkinSmoothingPasses, weights);

  // The largest kInfluences weights of each ring vertex, scaled to sum to 1.
  std::vector<int> order(joints);
  for (std::size_t v = 0; v < welded.size(); ++v) {
    if (!ring[welded[v]]) continue;
    const float* row = &weights[row_of[welded[v]] * joints];
    std::iota(order.begin(), order.end(), 0);
    std::partial_sort(order.begin(), order.begin() + std::min(kInfluences, joints), order.end(),
                      [&](int a, int b) { return row[a] > row[b]; });
    float kept = 0.0f;
    for (int k = 0; k < std::min(kInfluences, joints); ++k) kept += row[order[k]];
    for (int k = 0; k < kInfluences; ++k) {
      const bool used = k < joints && kept > 0.0f;
      result.joints[v][k] = used ? static_cast<std::uint16_t>(order[k]) : 0;
      result.weights[v][k] = used ? row[order[k]] / kept : 0.0f;
    }
  }
  return result;
}

}  // namespace sweepd::deform
