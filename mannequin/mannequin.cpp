#include "mannequin/mannequin.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "deform/mesh/disjoint_sets.h"
#include "deform/mesh/vertex_adjacency.h"
#include "mannequin/body_shape.h"
#include "mannequin/mannequin_anatomy.h"
#include "mannequin/marching_tetrahedra.h"
#include "mannequin/shortest_edge_decimation.h"
#include "mannequin/uv_atlas.h"

namespace sweepd::mannequin {

using deform::compute_vertex_normals;
using deform::kInfluences;
using deform::Model;
using deform::Skeleton;
using deform::vertex_adjacency;
using deform::VertexAdjacency;

namespace {

constexpr float kHeight = 1.75f;           // metres, feet to the top of the head
constexpr float kBlendRadius = 0.025f;     // fillet size where body parts meet (metres)
constexpr float kWeightBlendBand = 0.03f;  // parts this close to the nearest one share its skin
constexpr float kMinimumHalfAxisPerSpacing = 0.9f;  // thin parts stay visible to the grid
constexpr int kSmoothingIterations = 2;
// The grid is sampled for this many times the target's vertices (and at least
// kMinimumMarchedVertices), then decimated: marching tetrahedra alone needs a coarse grid for a
// small target, and a coarse grid loses fingers and wrists.
constexpr float kOversampling = 1.4f;
constexpr float kMinimumMarchedVertices = 30000.0f;
// Seam duplicates per welded vertex fall like 1 / sqrt(vertices): about 15 / sqrt(n).
constexpr float kSeamVerticesPerSqrtVertex = 15.0f;
// Marching tetrahedra gives about 4.5 vertices per spacing^2 of surface (edge crossings of the
// 7 Kuhn edge directions, averaged over orientations); the body has about 1.85 m^2 of skin.
constexpr float kVerticesTimesSpacingSquared = 4.5f * 1.85f;

// The triangle mesh of one polygonisation, before UV splitting.
struct WeldedSurface {
  std::vector<glm::vec3> positions;
  std::vector<std::uint32_t> indices;
};

// Keeps the connected piece with the most triangles (a coarse grid can cut off a fingertip).
void keep_largest_component(WeldedSurface& surface) {
  const std::size_t n = surface.positions.size();
  const std::vector<std::uint32_t> component = deform::vertex_components(surface.indices, n);
  std::vector<std::size_t> triangles_of_root(n, 0);
  for (std::size_t t = 0; t < surface.indices.size(); t += 3)
    ++triangles_of_root[component[surface.indices[t]]];
  const auto largest = static_cast<std::uint32_t>(
      std::max_element(triangles_of_root.begin(), triangles_of_root.end()) -
      triangles_of_root.begin());

  std::vector<std::uint32_t> new_index(n, UINT32_MAX);
  WeldedSurface kept;
  for (std::size_t t = 0; t < surface.indices.size(); t += 3) {
    if (component[surface.indices[t]] != largest) continue;
    for (int k = 0; k < 3; ++k) {
      std::uint32_t& mapped = new_index[surface.indices[t + k]];
      if (mapped == UINT32_MAX) {
        mapped = static_cast<std::uint32_t>(kept.positions.size());
        kept.positions.push_back(surface.positions[surface.indices[t + k]]);
      }
      kept.indices.push_back(mapped);
    }
  }
  surface = std::move(kept);
}

WeldedSurface polygonise(const BodyShape& body, float spacing) {
  SampleGrid grid;
  grid.spacing = spacing;
  // Two spare layers of grid points keep the outer layer outside the body.
  grid.origin = body.lower_bound() - 2.0f * spacing;
  const glm::vec3 extent = body.upper_bound() + 2.0f * spacing - grid.origin;
  grid.cells = glm::ivec3(glm::ceil(extent / spacing));
  IsoSurface iso;
  marching_tetrahedra(
      grid,
      [&body](const glm::vec3& lo, const glm::vec3& hi, std::span<const glm::vec3> points,
              std::span<float> values) { return body.evaluate_block(lo, hi, points, values); },
      iso);
  WeldedSurface surface{std::move(iso.positions), std::move(iso.indices)};
  keep_largest_component(surface);
  return surface;
}

// One Newton step from p towards the body's surface, at most half a grid spacing long.
glm::vec3 project_onto_surface(const BodyShape& body, float spacing, const glm::vec3& p) {
  const glm::vec3 gradient = body.gradient(p, 0.25f * spacing);
  const float gradient2 = glm::dot(gradient, gradient);
  if (!(gradient2 > 1e-12f)) return p;
  glm::vec3 step = -body.value(p) * gradient / gradient2;
  const float step_length = glm::length(step);
  if (step_length > 0.5f * spacing) step *= 0.5f * spacing / step_length;
  return p + step;
}

// Evens out the marching-tetrahedra triangles: each vertex moves halfway towards the centroid
// of its neighbours within the tangent plane, then back onto the surface (one Newton step).
void relax_on_surface(const BodyShape& body, float spacing, WeldedSurface& surface) {
  const VertexAdjacency adjacency = vertex_adjacency(surface.positions, surface.indices);
  std::vector<glm::vec3> moved(surface.positions.size());
  for (int iteration = 0; iteration < kSmoothingIterations; ++iteration) {
    for (std::size_t v = 0; v < surface.positions.size(); ++v) {
      const glm::vec3& p = surface.positions[v];
      glm::vec3 centroid(0.0f);
      const std::span<const std::uint32_t> ring =
          adjacency.neighbours(static_cast<std::uint32_t>(v));
      for (std::uint32_t u : ring) centroid += surface.positions[u];
      centroid /= static_cast<float>(ring.size());
      const glm::vec3 gradient = body.gradient(p, 0.25f * spacing);
      const float gradient2 = glm::dot(gradient, gradient);
      if (!(gradient2 > 1e-12f)) {
        moved[v] = p;
        continue;
      }
      const glm::vec3 normal = gradient / std::sqrt(gradient2);
      const glm::vec3 shift = centroid - p;
      moved[v] = project_onto_surface(body, spacing,
                                      p + 0.5f * (shift - glm::dot(shift, normal) * normal));
    }
    surface.positions.swap(moved);
  }
}

// Per welded vertex: the part it belongs to (the most inside one) and its part values.
std::vector<int> owning_parts(const BodyShape& body, const std::vector<glm::vec3>& positions) {
  std::vector<int> owner(positions.size(), 0);
  for (std::size_t v = 0; v < positions.size(); ++v) {
    float best = body.part_value(0, positions[v]);
    for (int p = 1; p < body.part_count(); ++p) {
      const float value = body.part_value(p, positions[v]);
      if (value < best) {
        best = value;
        owner[v] = p;
      }
    }
  }
  return owner;
}

// Skin weights: each part near the vertex contributes its chain's weights, fading out over
// kWeightBlendBand beyond the nearest part, so weights stay smooth where parts meet.
void skin_vertex(const MannequinAnatomy& anatomy, const BodyShape& body, const glm::vec3& p,
                 std::array<std::uint16_t, kInfluences>& joints,
                 std::array<float, kInfluences>& weights) {
  std::vector<float> part_values(body.part_count());
  for (int i = 0; i < body.part_count(); ++i) part_values[i] = body.part_value(i, p);
  const float nearest = *std::min_element(part_values.begin(), part_values.end());
  std::vector<float> joint_weight(anatomy.skeleton.size(), 0.0f);
  for (int i = 0; i < body.part_count(); ++i) {
    const float share = 1.0f - (part_values[i] - nearest) / kWeightBlendBand;
    if (share <= 0.0f) continue;
    std::array<JointWeight, 3> chain_weights;
    const int count = chain_skin_weights(anatomy.chains[body.part(i).skin_chain], p, chain_weights);
    for (int k = 0; k < count; ++k)
      joint_weight[chain_weights[k].joint] += share * chain_weights[k].weight;
  }
  std::vector<int> order(joint_weight.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return joint_weight[a] > joint_weight[b]; });
  float total = 0.0f;
  for (int k = 0; k < kInfluences; ++k) total += joint_weight[order[k]];
  for (int k = 0; k < kInfluences; ++k) {
    joints[k] = static_cast<std::uint16_t>(order[k]);
    weights[k] = joint_weight[order[k]] / total;
  }
}

// Renumbers the model's corners so that consecutive vertices are neighbours on the surface:
// the triangles in meshoptimizer's vertex-cache order, then the corners in the order those
// triangles first use them. The marched triangles come in grid-scan order, where a quarter of
// consecutive corners lie centimetres apart; compact vertex streams (protocol/README.md) store
// deltas between consecutive vertices, and the 72k mannequin's positions take about 20% fewer
// bytes in this order (bench/vertex_stream_bench.cpp). Only the numbering changes.
void order_corners_along_the_surface(UvAtlas& atlas) {
  std::vector<ChartCorner>& corners = atlas.corners;
  std::vector<glm::vec2>& uvs = atlas.uvs;
  std::vector<std::uint32_t>& indices = atlas.indices;
  std::vector<std::uint32_t> ordered(indices.size());
  meshopt_optimizeVertexCache(ordered.data(), indices.data(), indices.size(), corners.size());
  std::vector<std::uint32_t> new_index(corners.size());
  meshopt_optimizeVertexFetchRemap(new_index.data(), ordered.data(), ordered.size(),
                                   corners.size());  // every corner is used by a triangle
  std::vector<ChartCorner> renumbered_corners(corners.size());
  std::vector<glm::vec2> renumbered_uvs(uvs.size());
  for (std::size_t v = 0; v < corners.size(); ++v) {
    renumbered_corners[new_index[v]] = corners[v];
    renumbered_uvs[new_index[v]] = uvs[v];
  }
  for (std::uint32_t& index : ordered) index = new_index[index];
  corners = std::move(renumbered_corners);
  uvs = std::move(renumbered_uvs);
  indices = std::move(ordered);
}

}  // namespace

Model make_mannequin(const MannequinOptions& options) {
  if (options.target_vertices < kMannequinMinVertices ||
      options.target_vertices > kMannequinMaxVertices)
    throw std::invalid_argument(
        "mannequin target_vertices " + std::to_string(options.target_vertices) + " is outside " +
        std::to_string(kMannequinMinVertices) + " .. " + std::to_string(kMannequinMaxVertices));
  const MannequinAnatomy anatomy = make_mannequin_anatomy();
  const auto target = static_cast<float>(options.target_vertices);

  // Marching tetrahedra on a grid fine enough for kMinimumMarchedVertices (thin parts keep
  // their shape), then shortest-edge decimation down to the welded count that, with the UV
  // seam duplicates, gives the target; the duplicate share is re-measured and corrected.
  const float marched_target = std::max(kOversampling * target, kMinimumMarchedVertices);
  const float spacing = std::sqrt(kVerticesTimesSpacingSquared / marched_target);
  const BodyShape body(anatomy.parts, kBlendRadius, kMinimumHalfAxisPerSpacing * spacing);
  const WeldedSurface marched = polygonise(body, spacing);
  auto place = [&body, spacing](const glm::vec3& p) {
    return project_onto_surface(body, spacing, p);
  };
  float welded_target = target / (1.0f + kSeamVerticesPerSqrtVertex / std::sqrt(target));
  WeldedSurface surface;
  UvAtlas atlas;
  for (int attempt = 0; attempt < 3; ++attempt) {
    surface = marched;
    decimate_shortest_edges(surface.positions, surface.indices,
                            static_cast<std::size_t>(welded_target), place);
    relax_on_surface(body, spacing, surface);
    atlas = make_uv_atlas(body, surface.positions, surface.indices,
                          owning_parts(body, surface.positions));
    const auto count = static_cast<float>(atlas.corners.size());
    if (std::abs(count / target - 1.0f) < 0.03f) break;
    welded_target *= target / count;
  }
  order_corners_along_the_surface(atlas);
  const std::vector<ChartCorner>& corners = atlas.corners;

  const std::vector<glm::vec3> welded_normals =
      compute_vertex_normals(surface.positions, surface.indices);
  Model model;
  model.name = "mannequin";
  model.skeleton = anatomy.skeleton;
  model.indices = std::move(atlas.indices);
  model.uvs = std::move(atlas.uvs);
  const std::size_t n = corners.size();
  model.positions.resize(n);
  model.normals.resize(n);
  model.skin_joints.resize(n);
  model.skin_weights.resize(n);
  std::vector<std::array<std::uint16_t, kInfluences>> welded_joints(surface.positions.size());
  std::vector<std::array<float, kInfluences>> welded_weights(surface.positions.size());
  for (std::size_t v = 0; v < surface.positions.size(); ++v)
    skin_vertex(anatomy, body, surface.positions[v], welded_joints[v], welded_weights[v]);

  // Feet on the ground and exactly the designed height: the fillets, the thickening of thin
  // parts and the grid move the soles and the crown by millimetres, so scale the model about
  // its lowest point to kHeight and put that point at y = 0 (skeleton included).
  float lowest = surface.positions.front().y, highest = lowest;
  for (const glm::vec3& p : surface.positions) {
    lowest = std::min(lowest, p.y);
    highest = std::max(highest, p.y);
  }
  const float scale = kHeight / (highest - lowest);
  const glm::vec3 ground(0.0f, lowest, 0.0f);
  model.skeleton.joints[0].rest_translation =
      (model.skeleton.joints[0].rest_translation - ground) * scale;
  for (std::size_t j = 1; j < model.skeleton.joints.size(); ++j)
    model.skeleton.joints[j].rest_translation *= scale;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t w = corners[i].welded;
    model.positions[i] = (surface.positions[w] - ground) * scale;
    model.normals[i] = welded_normals[w];
    model.skin_joints[i] = welded_joints[w];
    model.skin_weights[i] = welded_weights[w];
  }
  return model;
}

}  // namespace sweepd::mannequin
