#include "deform/blending/sweep_blending.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "deform/binding/bind_threads.h"
#include "deform/mesh/length_weighted_smoothing.h"
#include "deform/mesh/surface_distance.h"

namespace sweepd::deform {

namespace {

constexpr int kPartCount = static_cast<int>(BodyPart::kRightFoot) + 1;
constexpr int kShareSmoothingPasses = 150;
// kShareSmoothingPasses were measured on meshes whose edges where the shares are smoothed have a
// median length of at least kMeasuredEdgeOfReach of the reach below (the 20k mannequin 0.238,
// the shared male 0.50, the 3k mannequin 0.68). Each pass spreads a share's jump about one edge
// further, and a diffusion's spread grows with the square root of its passes, so a finer mesh
// gets passes in proportion to (kMeasuredEdgeOfReach · reach / median edge)² (the 72k mannequin,
// 0.125: 511), up to kMostShareSmoothingPasses. With 150 there the arm's share fell 0.11 across
// one 8 mm edge on the side of the chest, 4.29x edge stretch over cmu_01_03 (every 20th frame).
constexpr float kMeasuredEdgeOfReach = 0.23f;
constexpr int kMostShareSmoothingPasses = 2000;
// How far from where a leg meets another sweep the share smoothing reaches over the swept skin,
// as a fraction of the longest sweep's chain (the leg's, hip to ankle: 4.2 cm on the mannequin,
// 4.3 cm on the male). The worst hips edge over cmu_01_03, male / mannequin: 0 2.83 / 3.63x,
// 0.02 2.82 / 2.88, 0.03 2.67 / 2.46, 0.05 2.61 / 2.44, 0.08 2.53 / 2.43; cmu_01_01 within
// 0.03x, the RiggedFigure unchanged.
constexpr float kShareSmoothingReach = 0.05f;
// The same around where an arm meets another sweep (the armpit, the side of the chest), half as
// far (2.2 cm on the male). Without it an arm-only vertex bordered one the torso shares, and the
// arm's share fell 0.37 across one 11 mm edge under the heavy female's armpit: 6.16x with her
// arm overhead (cmu_01_03 frame 3850; LBS 3.50 on that edge). With it her worst limb or torso
// edge over cmu_01_03, every 100th frame, 5.85 -> 2.97x (LBS 8.10), and the corpus gate's worse
// pairs 449 -> 330 for her, 400 -> 381 for the male. The legs' 0.05 won more on the heavy male
// (cmu_01_03 3.88 -> 3.65x against 3.85x here) but moved the male's closed arm region 2.2 points
// from the sweep's integral at a 150° elbow turn (issue 5's bound: 2; 1.8 here).
constexpr float kArmShareSmoothingReach = 0.025f;
// The neck's hand-over to the head's skinning starts where the head's skin weight passes
// kHeadHandoverStartWeight and is complete kHeadHandoverLength neck lengths (the neck chain's
// joint-to-joint length; 10.2 cm on the shared male) further along the surface. On the male
// and cmu_01_01's 88° head turn: starting at 0.2 the throat's skinned share spreads lower and
// the neck region loses 11.5 % of its volume there (5.8 % from 0.3, 4.2 % from 0.5); lengths
// of 1.0-1.2 stretch the throat 2.5-2.7x at most (1.3: 2.8x; from 1.4 the ramp reaches the lips,
// 3.5x on their 1.6 mm edges), and from 1.1 on it reaches the mouth's inside, whose layers 1 mm
// apart then cross each other (36 more crossing triangle pairs at cmu_01_01 frame 32).
constexpr float kHeadHandoverStartWeight = 0.5f;
constexpr float kHeadHandoverLength = 1.0f;
// The skinned share rises from 0 to 1 over no less than kHandoverReach × the longest sweep's
// chain along the surface (4.3 cm on the shared male). Where two methods meet, an edge stretches
// by the share's change across it times how far apart the sweep and skinning put its vertices:
// the wrists' and the neck's plane pairs (0.12 of a short last link) and the painted weights
// made steps of 0.2-0.6 across one edge, and those edges were most of the corpus gate's worse
// (frame, region) pairs (wrists 913, neck and head 794 of 4768; issue 47). Corpus gate, every
// body as is, mirrored and at 0.6x: 4768 -> 4204 worse pairs; each body's sum lower but the
// RiggedFigure's (988, unchanged), no worst limb or torso stretch higher. A longer reach wins
// more pairs (0.1: 3705) but hands the forearm's twist to skinning: a 150° pronation kept 0.73
// of a forearm section (0.93 at 0.05 and without the limit; LBS 0.68), and from 0.07 a leg's
// crease at its keys turns the smooth orientation curve's gain into a loss (cmu_01_03).
constexpr float kHandoverReach = 0.05f;

float smoothstep01(float x) {
  x = std::clamp(x, 0.0f, 1.0f);
  return x * x * (3.0f - 2.0f * x);
}

// A region between two parallel planes: 0 before the first, 1 after the second.
struct PlanePair {
  glm::vec3 centre{0.0f};
  glm::vec3 direction{0.0f};
  float half_width = 1.0f;
  float weight(glm::vec3 p) const {
    return smoothstep01((glm::dot(p - centre, direction) + half_width) / (2.0f * half_width));
  }
};

// Planes centred at `centre`, orthogonal to the link from `from` to `to`.
PlanePair planes_at(glm::vec3 centre, glm::vec3 from, glm::vec3 to, float half_width_fraction) {
  PlanePair pair;
  pair.centre = centre;
  pair.direction = glm::normalize(to - from);
  pair.half_width = half_width_fraction * glm::length(to - from);
  return pair;
}

// Point-to-point length of a sweep's rest path (BoundSweep::rest_path).
float path_length(std::span<const glm::vec3> path) {
  float length = 0.0f;
  for (std::size_t i = 1; i < path.size(); ++i) length += glm::length(path[i] - path[i - 1]);
  return length;
}

// kShareSmoothingPasses, or more on a mesh finer than those they were measured on.
int share_smoothing_passes(std::vector<float>& edge_lengths, float reach) {
  if (edge_lengths.empty() || !(reach > 0.0f)) return kShareSmoothingPasses;
  const auto middle = edge_lengths.begin() + edge_lengths.size() / 2;
  std::nth_element(edge_lengths.begin(), middle, edge_lengths.end());
  const float finer = kMeasuredEdgeOfReach * reach / std::max(*middle, 1e-9f);
  if (!(finer > 1.0f)) return kShareSmoothingPasses;
  return static_cast<int>(
      std::min<float>(std::ceil(kShareSmoothingPasses * finer * finer), kMostShareSmoothingPasses));
}

// Where sweeps meet (a vertex with shares of two sweeps or more), and on the swept skin within
// column_reach[c] along the surface of where sweep c meets another (a leg's, an arm's; 0: no
// reach), replaces each vertex's row of shares by half its own plus half its mesh neighbours'
// mean, share_smoothing_passes() times (for the longest reach), each neighbour weighted by
// 1 / edge length (the other vertices' rows stay as they are and hold the border). Smoothing the meeting vertices alone left the border where they end, so a share
// could still fall 0.16 across one 8.7 mm edge: at the back of the mannequin's crotch a vertex
// of the raised thigh's sweep alone, beside one with 9 % of the other leg's, stretched 3.63x
// at cmu_01_03's high knee (frame 3249); with the border spread over the skin around the
// crotch, 2.44x.
// Skin weights may jump between neighbouring vertices (the shared male's gluteal cleft, the
// crotch midline), and a share jump between two sweeps that disagree in a deep pose tears the
// skin (14x edge stretch in a CMU crouch). Weighting by inverse length spreads a jump over a
// distance rather than over a count of edges, which matters where the mesh is dense: the
// male's crotch midline has 2-4 mm edges, where 48 plain passes left the left and right leg
// shares 0.13 apart across 2 mm (6.1x stretch in cmu_01_03). Now no edge where both legs share
// stretches over 2.2x (cmu_01_01) and 2.8x (cmu_01_03: the lower back, bent 52° forward);
// more passes spread the leg shares further up the back and stretch it more there.
// The wrists' and ankles' hand-overs keep their planes: smoothing them lets twist collapse the
// forearm, and leaks leg shares into the feet. The neck's hand-over to the head has its own
// ramp along the surface (head_handover_by_distance).
void smooth_over_mesh(const VertexAdjacency& adjacency, std::span<const float> column_reach,
                      std::vector<float>& shares) {
  const int columns = static_cast<int>(column_reach.size()) + 1;  // the sweeps', then skinning's
  std::vector<int> sweeps(adjacency.vertex_count(), 0);  // how many sweeps share each vertex
  for (std::uint32_t v = 0; v < adjacency.vertex_count(); ++v)
    for (int c = 0; c + 1 < columns; ++c) sweeps[v] += shares[v * columns + c] > 0.0f;
  // Per distinct reach: how far each vertex lies from where a sweep with that reach meets
  // another; a swept vertex within the reach is smoothed.
  std::vector<bool> near(adjacency.vertex_count(), false);
  std::vector<float> reaches(column_reach.begin(), column_reach.end());
  std::sort(reaches.begin(), reaches.end());
  reaches.erase(std::unique(reaches.begin(), reaches.end()), reaches.end());
  for (float reach : reaches) {
    if (!(reach > 0.0f)) continue;
    std::vector<bool> at_junction(adjacency.vertex_count(), false);
    for (std::uint32_t v = 0; v < adjacency.vertex_count(); ++v)
      for (int c = 0; c + 1 < columns; ++c)
        if (column_reach[c] == reach && shares[v * columns + c] > 0.0f && sweeps[v] >= 2)
          at_junction[v] = true;
    const std::vector<float> from_junction = distance_along_edges(adjacency, at_junction);
    for (std::uint32_t v = 0; v < adjacency.vertex_count(); ++v)
      if (sweeps[v] >= 1 && from_junction[v] <= reach) near[v] = true;
  }
  LengthWeightedSmoothing near_junctions;
  std::vector<float> edge_lengths;
  for (std::uint32_t v = 0; v < adjacency.vertex_count(); ++v) {
    if (!(sweeps[v] >= 2 || near[v]) || adjacency.neighbours(v).empty()) continue;
    near_junctions.add(v, adjacency.neighbours(v), adjacency.lengths(v),
                       [](std::uint32_t u) { return u; });
    edge_lengths.insert(edge_lengths.end(), adjacency.lengths(v).begin(),
                        adjacency.lengths(v).end());
  }
  const float longest_reach = reaches.empty() ? 0.0f : reaches.back();
  near_junctions.smooth(columns, share_smoothing_passes(edge_lengths, longest_reach), shares,
                        kBindThreads);
}

// The neck's hand-over to the head's skinning, per welded vertex: 0 up to where the head's skin
// weight passes kHeadHandoverStartWeight, then rising linearly with the distance from there
// along the surface, to 1 at kHeadHandoverLength neck lengths. The shared male's painted head
// weights reach 6 cm down the throat and rise from 0.4 to 0.9 within 2 cm on its sides; handing
// over by the weight itself (2w - 1, then smoothed over the mesh) put the whole hand-over on
// 2.5 cm of skin under the chin, where the head's skinning and the neck sweep part by 8.5 cm
// when the head turns 88° (cmu_01_01 frame 1046: 3.43x), and a skinned share on the steep sides
// stretches them as LBS does (3.25x). The ramp spreads it over the throat and the jaw's
// underside; the jaw, further on, stays rigid with the head.
// adjacency: the welded mesh's; head_weight: per welded vertex.
std::vector<float> head_handover_by_distance(const VertexAdjacency& adjacency,
                                             std::span<const float> head_weight,
                                             float neck_length) {
  std::vector<bool> before_start(adjacency.vertex_count());
  for (std::size_t v = 0; v < before_start.size(); ++v)
    before_start[v] = head_weight[v] <= kHeadHandoverStartWeight;
  std::vector<float> handover = distance_along_edges(adjacency, before_start);
  for (float& h : handover) h = std::min(1.0f, h / (kHeadHandoverLength * neck_length));
  return handover;
}

// Limits how fast the skinned share rises along the surface: a vertex within distance d of one
// whose skinned share is s takes at least s - d / reach. Only raises shares (the sweeps' shares
// shrink in proportion), so a gentle hand-over stays as it was and a step spreads back over the
// swept skin, towards the sweep, never into what skinning already holds whole.
// shares: per welded vertex, one column per sweep and then skinning's (columns in all).
void limit_handover_slope(const VertexAdjacency& adjacency, int columns, float reach,
                          std::vector<float>& shares) {
  const int skinned = columns - 1;
  std::vector<float> start(adjacency.vertex_count());
  for (std::size_t v = 0; v < start.size(); ++v)
    start[v] = reach * (1.0f - shares[v * columns + skinned]);
  const std::vector<float> reached = distance_along_edges(adjacency, start);
  for (std::size_t v = 0; v < start.size(); ++v) {
    float* row = &shares[v * columns];
    const float limited = 1.0f - reached[v] / reach;
    if (!(limited > row[skinned])) continue;
    const float keep = (1.0f - limited) / (1.0f - row[skinned]);  // row[skinned] < limited <= 1
    for (int s = 0; s < skinned; ++s) row[s] *= keep;
    row[skinned] = limited;
  }
}

}  // namespace

BodyPart end_part(BodyPart sweep_part) {
  switch (sweep_part) {
    case BodyPart::kNeck:
      return BodyPart::kHead;
    case BodyPart::kLeftArm:
      return BodyPart::kLeftHand;
    case BodyPart::kRightArm:
      return BodyPart::kRightHand;
    case BodyPart::kLeftLeg:
      return BodyPart::kLeftFoot;
    case BodyPart::kRightLeg:
      return BodyPart::kRightFoot;
    default:
      return BodyPart::kNone;
  }
}

std::vector<VertexBinding> blend_shares(const Model& model, const WeldedMesh& mesh,
                                        const RigMap& rig, std::span<const glm::mat4> world_rest,
                                        std::span<const BoundSweep> sweeps,
                                        const BindOptions& options) {
  const std::vector<BodyPart> joint_part = label_joints(rig, model.skeleton);
  const int sweep_count = static_cast<int>(sweeps.size());
  std::vector<PlanePair> start(sweep_count), finish(sweep_count);
  PlanePair torso_top, torso_bottom;  // beyond the torso's end keys, skinning takes over
  int torso = -1;
  std::vector<float> length(sweep_count);
  for (int s = 0; s < sweep_count; ++s) {
    const std::vector<glm::vec3> path = sweeps[s].rest_path(world_rest);
    const int n = static_cast<int>(path.size());
    length[s] = path_length(path);
    if (sweeps[s].part == BodyPart::kTorso) torso = s;
    start[s] = planes_at(path[0], path[0], path[1], options.transition_half_width);
    finish[s] = planes_at(path[n - 1], path[n - 2], path[n - 1], options.end_blend_half_width);
    // A leg hands over by the ankle (the header says why an arm does not).
    if (sweeps[s].part == BodyPart::kLeftLeg || sweeps[s].part == BodyPart::kRightLeg)
      finish[s].centre -= finish[s].half_width * finish[s].direction;
    if (s == torso) {
      torso_top = finish[s];
      torso_top.centre += torso_top.half_width * torso_top.direction;
      torso_bottom = planes_at(path[0], path[1], path[0], options.end_blend_half_width);
      torso_bottom.centre += torso_bottom.half_width * torso_bottom.direction;
    }
  }

  // Shares per welded vertex: one per sweep, then the skinned share; each row sums to 1.
  const std::size_t welded_count = mesh.vertex_count();
  const std::vector<std::uint32_t>& welded = mesh.welded_id;
  std::vector<float> head_weight(welded_count, 0.0f);
  for (std::size_t v = 0; v < model.vertex_count(); ++v) {
    float weight = 0.0f;
    for (int k = 0; k < kInfluences; ++k)
      if (joint_part[model.skin_joints[v][k]] == BodyPart::kHead)
        weight += model.skin_weights[v][k];
    head_weight[welded[v]] = weight;
  }
  // A neck whose bone carries the head has the head's weight all along it: its hand-over is
  // its planes', as a forearm's that carries the hand.
  std::vector<float> head_handover;
  for (int s = 0; s < sweep_count; ++s)
    if (sweeps[s].part == BodyPart::kNeck && !sweeps[s].ends_on_carried_end())
      head_handover = head_handover_by_distance(mesh.adjacency, head_weight, length[s]);

  const int columns = sweep_count + 1;
  std::vector<float> shares(welded_count * columns, 0.0f);
  std::vector<float> share(sweep_count);
  for (std::size_t v = 0; v < model.vertex_count(); ++v) {
    std::array<float, kPartCount> skin{};
    for (int k = 0; k < kInfluences; ++k)
      skin[static_cast<int>(joint_part[model.skin_joints[v][k]])] += model.skin_weights[v][k];
    const glm::vec3 p = model.positions[v];

    float limbs = 0.0f, skinned = skin[static_cast<int>(BodyPart::kNone)];
    for (int s = 0; s < sweep_count; ++s) {
      share[s] = 0.0f;
      if (s == torso) continue;
      const BodyPart part = sweeps[s].part, end = end_part(part);
      const float mask = std::min(1.0f, (torso >= 0 ? 2.0f : 1.0f) *
                                            (skin[static_cast<int>(part)] + skin[static_cast<int>(end)]));
      share[s] = start[s].weight(p) * mask;
      limbs += share[s];
    }
    if (limbs > 1.0f)
      for (float& s : share) s /= limbs;
    const float rest_of_body = std::max(0.0f, 1.0f - std::min(limbs, 1.0f));
    if (torso >= 0) {
      share[torso] = rest_of_body;
      // Above the chest key (shoulders, upper chest) and below the pelvis key the torso sweep
      // only extrapolates; the model's own skinning (clavicles, hips) knows better.
      skinned += share[torso] * std::max(torso_top.weight(p), torso_bottom.weight(p));
    } else {
      skinned += rest_of_body;  // a one-joint torso is skinned: what the limbs leave is its
    }
    for (int s = 0; s < sweep_count; ++s) {
      if (s == torso || share[s] == 0.0f) continue;
      // The hand's or foot's own skin weight takes over once it passes one half; the head's
      // by its surface ramp.
      const float end_skin = skin[static_cast<int>(end_part(sweeps[s].part))];
      const float by_skin = sweeps[s].ends_on_carried_end() ? 0.0f
                            : sweeps[s].part == BodyPart::kNeck
                                ? head_handover[welded[v]]
                                : std::clamp(2.0f * end_skin - 1.0f, 0.0f, 1.0f);
      skinned += share[s] * std::max(finish[s].weight(p), by_skin);
    }
    skinned = std::clamp(skinned, 0.0f, 1.0f);
    float total = 0.0f;
    for (float s : share) total += s;
    float* row = &shares[welded[v] * columns];
    if (total <= 0.0f) skinned = 1.0f;
    for (int s = 0; s < sweep_count; ++s)
      row[s] = total > 0.0f ? share[s] * (1.0f - skinned) / total : 0.0f;
    row[sweep_count] = skinned;
  }
  const float longest_chain =
      sweep_count > 0 ? *std::max_element(length.begin(), length.end()) : 0.0f;
  std::vector<float> column_reach(sweep_count, 0.0f);
  for (int s = 0; s < sweep_count; ++s) {
    const BodyPart part = sweeps[s].part;
    if (part == BodyPart::kLeftLeg || part == BodyPart::kRightLeg)
      column_reach[s] = kShareSmoothingReach * longest_chain;
    else if (part == BodyPart::kLeftArm || part == BodyPart::kRightArm)
      column_reach[s] = kArmShareSmoothingReach * longest_chain;
  }
  smooth_over_mesh(mesh.adjacency, column_reach, shares);
  limit_handover_slope(mesh.adjacency, columns, kHandoverReach * longest_chain, shares);

  // Keep the kSweepsPerVertex largest sweep shares, scaled to fill what skinning leaves.
  std::vector<VertexBinding> result(model.vertex_count());
  std::vector<int> order(sweep_count);
  for (std::size_t v = 0; v < model.vertex_count(); ++v) {
    const float* row = &shares[welded[v] * columns];
    VertexBinding& binding = result[v];
    float sweeps_total = 0.0f, kept = 0.0f;
    for (int s = 0; s < sweep_count; ++s) sweeps_total += row[s];
    for (int s = 0; s < sweep_count; ++s) order[s] = s;
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return row[a] > row[b]; });
    for (int k = 0; k < std::min(kSweepsPerVertex, sweep_count) && row[order[k]] > 0.0f; ++k) {
      binding.sweep[k] = static_cast<std::int16_t>(order[k]);
      binding.weight[k] = row[order[k]];
      kept += row[order[k]];
    }
    if (kept <= 1e-6f) {
      binding = VertexBinding{};
      binding.skin_weight = 1.0f;
      continue;
    }
    float sum = 0.0f;
    for (int k = 0; k < kSweepsPerVertex; ++k) sum += binding.weight[k] *= sweeps_total / kept;
    binding.skin_weight = std::max(0.0f, 1.0f - sum);
  }
  return result;
}

}  // namespace sweepd::deform
