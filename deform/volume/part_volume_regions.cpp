#include "deform/volume/part_volume_regions.h"

#include <map>

#include "deform/mesh/mesh_topology.h"

namespace sweepd::deform {
namespace {

double signed_tetra_volume(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  return glm::dot(a, glm::cross(b, c)) / 6.0;
}

}  // namespace

PartVolumeRegions::PartVolumeRegions(const BoundModel& bound) {
  const Model& model = bound.model;
  std::size_t welded_count = 0;
  const std::vector<std::uint32_t> welded =
      weld_coincident_positions(model.positions, &welded_count);
  std::vector<std::uint32_t> representative(welded_count);
  for (std::size_t v = 0; v < welded.size(); ++v)
    representative[welded[v]] = static_cast<std::uint32_t>(v);
  regions_.resize(bound.sweeps.size());
  std::vector<float> weight(model.vertex_count());
  for (std::size_t s = 0; s < bound.sweeps.size(); ++s) {
    for (std::size_t v = 0; v < weight.size(); ++v) {
      weight[v] = 0.0f;
      for (int k = 0; k < kSweepsPerVertex; ++k)
        if (bound.vertices[v].sweep[k] == static_cast<int>(s))
          weight[v] += bound.vertices[v].weight[k];
    }
    Region& region = regions_[s];
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;  // welded edge → count
    for (std::size_t t = 0; t + 2 < model.indices.size(); t += 3) {
      const std::uint32_t* tri = &model.indices[t];
      if (weight[tri[0]] + weight[tri[1]] + weight[tri[2]] < 1.5f) continue;
      for (int k = 0; k < 3; ++k) {
        region.triangles.push_back(tri[k]);
        ++directed[{welded[tri[k]], welded[tri[(k + 1) % 3]]}];
      }
    }
    // Boundary edges: directed edges whose reverse is not in the region; chained into loops.
    std::multimap<std::uint32_t, std::uint32_t> next;
    for (const auto& [edge, count] : directed) {
      const auto reverse = directed.find({edge.second, edge.first});
      const int unmatched = count - (reverse == directed.end() ? 0 : reverse->second);
      for (int i = 0; i < unmatched; ++i) next.emplace(edge.first, edge.second);
    }
    region.loop_starts.push_back(0);
    while (!next.empty()) {
      const std::uint32_t start = next.begin()->first;
      std::uint32_t at = start;
      do {
        const auto it = next.find(at);
        if (it == next.end()) break;  // an open chain (cannot happen on a closed mesh)
        region.loop_vertices.push_back(representative[at]);
        at = it->second;
        next.erase(it);
      } while (at != start);
      region.loop_starts.push_back(static_cast<std::uint32_t>(region.loop_vertices.size()));
    }
  }
}

double PartVolumeRegions::volume(int sweep, std::span<const glm::vec3> positions) const {
  const Region& region = regions_[sweep];
  if (region.triangles.empty()) return 0.0;
  const glm::dvec3 origin = positions[region.triangles[0]];
  auto at = [&](std::uint32_t v) { return glm::dvec3(positions[v]) - origin; };
  double volume = 0.0;
  for (std::size_t t = 0; t + 2 < region.triangles.size(); t += 3)
    volume += signed_tetra_volume(at(region.triangles[t]), at(region.triangles[t + 1]),
                                  at(region.triangles[t + 2]));
  for (std::size_t l = 0; l + 1 < region.loop_starts.size(); ++l) {
    const std::uint32_t begin = region.loop_starts[l], end = region.loop_starts[l + 1];
    glm::dvec3 centre(0.0);
    for (std::uint32_t i = begin; i < end; ++i) centre += at(region.loop_vertices[i]);
    centre /= static_cast<double>(end - begin);
    for (std::uint32_t i = begin; i < end; ++i) {  // cap triangle (centre, b, a) of edge a→b
      const std::uint32_t j = i + 1 < end ? i + 1 : begin;
      volume +=
          signed_tetra_volume(centre, at(region.loop_vertices[j]), at(region.loop_vertices[i]));
    }
  }
  return volume;
}

}  // namespace sweepd::deform
