#include "mannequin/uv_atlas.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>

namespace sweepd::mannequin {

namespace {

constexpr float kMargin = 0.02f;  // of a tile, between charts (and between loose triangles)
constexpr float kUSpan = 1.5f;    // room right of u = 1 for seam-crossing triangles
// UV interiors closer than this (UV units, a thousandth of a texel at 1024) count as touching.
constexpr double kTouching = 1e-7;

// Chart c fills tile (c % columns, c / columns) of the square atlas; local is in [0, 1]^2.
glm::vec2 tile_uv(int tile, int columns, glm::vec2 local) {
  const float size = 1.0f / static_cast<float>(columns);
  return {
      size * (static_cast<float>(tile % columns) + kMargin + (1.0f - 2.0f * kMargin) * local.x),
      size * (static_cast<float>(tile / columns) + kMargin + (1.0f - 2.0f * kMargin) * local.y)};
}

double signed_area(const std::array<glm::vec2, 3>& uv) {
  const glm::dvec2 a = uv[0], b = uv[1], c = uv[2];
  return 0.5 * glm::determinant(glm::dmat2(b - a, c - a));
}

// A triangle in a part's chart: its corners' UVs and which lie right of the cylinder seam.
struct Placement {
  int chart = -1;  // -1: loose
  std::array<bool, 3> wrapped{};
  std::array<glm::vec2, 3> uv{};
};

// The triangle unrolled in `chart`; chart -1 when it folds there (or is flat).
Placement place_in_chart(const BodyShape& body, int columns, std::span<const glm::vec3> positions,
                         const std::uint32_t* tri, int chart) {
  Placement placed;
  PartCoordinates coordinates[3];
  float lowest = 1.0f, highest = 0.0f;
  for (int k = 0; k < 3; ++k) {
    coordinates[k] = body.part_coordinates(chart, positions[tri[k]]);
    lowest = std::min(lowest, coordinates[k].angle);
    highest = std::max(highest, coordinates[k].angle);
  }
  const bool crosses_seam = highest - lowest > 0.5f;
  for (int k = 0; k < 3; ++k) {
    placed.wrapped[k] = crosses_seam && coordinates[k].angle < 0.5f;
    const float u =
        std::min((coordinates[k].angle + (placed.wrapped[k] ? 1.0f : 0.0f)) / kUSpan, 1.0f);
    placed.uv[k] = tile_uv(chart, columns, {u, coordinates[k].axial});
  }
  if (signed_area(placed.uv) > 0.0) placed.chart = chart;
  return placed;
}

// Whether two UV triangles' interiors intersect (separating axes: the six edge normals).
bool interiors_overlap(const std::array<glm::vec2, 3>& a, const std::array<glm::vec2, 3>& b) {
  for (const auto* edges_of : {&a, &b})
    for (int k = 0; k < 3; ++k) {
      const glm::dvec2 edge = glm::dvec2((*edges_of)[(k + 1) % 3]) - glm::dvec2((*edges_of)[k]);
      const glm::dvec2 axis(-edge.y, edge.x);
      double lo_a = 1e30, hi_a = -1e30, lo_b = 1e30, hi_b = -1e30;
      for (int i = 0; i < 3; ++i) {
        const double pa = glm::dot(axis, glm::dvec2(a[i])), pb = glm::dot(axis, glm::dvec2(b[i]));
        lo_a = std::min(lo_a, pa), hi_a = std::max(hi_a, pa);
        lo_b = std::min(lo_b, pb), hi_b = std::max(hi_b, pb);
      }
      const double touching = kTouching * glm::length(axis);
      if (hi_a <= lo_b + touching || hi_b <= lo_a + touching) return false;
    }
  return true;
}

// Sends to the loose tile every charted triangle whose UV interior overlaps another's (a
// chart folds over itself where a part's surface turns back towards its axis: both layers go).
void loosen_overlaps(std::vector<Placement>& placed) {
  // Buckets of a grid about as fine as the triangles, keyed by cell; pairs sharing a cell
  // are tested (a pair may be tested in several cells: harmless).
  const auto cells = static_cast<int>(
      std::clamp(2.0 * std::sqrt(static_cast<double>(placed.size())), 64.0, 4096.0));
  std::vector<std::pair<std::uint64_t, std::uint32_t>> in_cell;
  for (std::uint32_t t = 0; t < placed.size(); ++t) {
    if (placed[t].chart < 0) continue;
    const auto& uv = placed[t].uv;
    const glm::ivec2 lo =
        glm::clamp(glm::ivec2(glm::min(uv[0], glm::min(uv[1], uv[2])) * static_cast<float>(cells)),
                   0, cells - 1);
    const glm::ivec2 hi =
        glm::clamp(glm::ivec2(glm::max(uv[0], glm::max(uv[1], uv[2])) * static_cast<float>(cells)),
                   0, cells - 1);
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x)
        in_cell.push_back({static_cast<std::uint64_t>(y) * cells + x, t});
  }
  std::sort(in_cell.begin(), in_cell.end());
  std::vector<bool> overlapping(placed.size(), false);
  for (std::size_t begin = 0; begin < in_cell.size();) {
    std::size_t end = begin;
    while (end < in_cell.size() && in_cell[end].first == in_cell[begin].first) ++end;
    for (std::size_t i = begin; i < end; ++i)
      for (std::size_t j = i + 1; j < end; ++j) {
        const std::uint32_t s = in_cell[i].second, t = in_cell[j].second;
        if (interiors_overlap(placed[s].uv, placed[t].uv)) overlapping[s] = overlapping[t] = true;
      }
    begin = end;
  }
  for (std::size_t t = 0; t < placed.size(); ++t)
    if (overlapping[t]) placed[t].chart = -1;
}

// Lays the loose triangles out flat (their own shape, one scale for all, counter-clockwise)
// in a grid of cells filling the loose tile.
void lay_out_loose(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                   int tile, int columns, std::vector<Placement>& placed) {
  std::vector<std::size_t> loose;
  for (std::size_t t = 0; t < placed.size(); ++t)
    if (placed[t].chart < 0) loose.push_back(t);
  if (loose.empty()) return;
  const int per_row = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(loose.size()))));
  std::vector<std::array<glm::vec2, 3>> flat(loose.size());
  float extent = 0.0f;
  for (std::size_t i = 0; i < loose.size(); ++i) {
    const std::uint32_t* tri = &indices[3 * loose[i]];
    const glm::vec3 e1 = positions[tri[1]] - positions[tri[0]];
    const glm::vec3 e2 = positions[tri[2]] - positions[tri[0]];
    const float length = glm::length(e1);
    const float along = glm::dot(e2, e1) / length;
    const float across = glm::length(glm::cross(e1, e2)) / length;
    const float left = std::min(0.0f, along);
    flat[i] = {glm::vec2(-left, 0.0f), glm::vec2(length - left, 0.0f),
               glm::vec2(along - left, across)};
    extent = std::max({extent, std::max(length, along) - left, across});
  }
  const float cell = 1.0f / static_cast<float>(per_row);
  const float scale = cell * (1.0f - 2.0f * kMargin) / extent;
  for (std::size_t i = 0; i < loose.size(); ++i) {
    const glm::vec2 origin(cell * (static_cast<float>(static_cast<int>(i) % per_row) + kMargin),
                           cell * (static_cast<float>(static_cast<int>(i) / per_row) + kMargin));
    Placement& p = placed[loose[i]];
    for (int k = 0; k < 3; ++k) p.uv[k] = tile_uv(tile, columns, origin + scale * flat[i][k]);
  }
}

}  // namespace

UvAtlas make_uv_atlas(const BodyShape& body, std::span<const glm::vec3> positions,
                      std::span<const std::uint32_t> indices, std::span<const int> owner) {
  const int loose_tile = body.part_count();
  const int columns = static_cast<int>(std::ceil(std::sqrt(static_cast<float>(loose_tile + 1))));
  // Each triangle goes to the chart most of its corners belong to, else to another of its
  // corners' charts where it does not fold, else loose.
  std::vector<Placement> placed(indices.size() / 3);
  for (std::size_t t = 0; t < placed.size(); ++t) {
    const std::uint32_t* tri = &indices[3 * t];
    const int a = owner[tri[0]], b = owner[tri[1]], c = owner[tri[2]];
    const int majority = (a == b || a == c) ? a : (b == c ? b : std::min({a, b, c}));
    for (int chart : {majority, a, b, c}) {
      placed[t] = place_in_chart(body, columns, positions, tri, chart);
      if (placed[t].chart >= 0) break;
    }
  }
  loosen_overlaps(placed);
  lay_out_loose(positions, indices, loose_tile, columns, placed);

  UvAtlas atlas;
  std::unordered_map<std::uint64_t, std::uint32_t> corner_of_key;
  corner_of_key.reserve(positions.size() * 5 / 4);
  atlas.indices.reserve(indices.size());
  for (std::size_t t = 0; t < placed.size(); ++t) {
    const Placement& p = placed[t];
    atlas.loose_triangles += p.chart < 0;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t welded = indices[3 * t + k];
      if (p.chart < 0) {  // a loose triangle's corners are its own
        atlas.indices.push_back(static_cast<std::uint32_t>(atlas.corners.size()));
        atlas.corners.push_back({welded, loose_tile, false});
        atlas.uvs.push_back(p.uv[k]);
        continue;
      }
      const std::uint64_t key = (static_cast<std::uint64_t>(welded) << 8) |
                                (static_cast<std::uint64_t>(p.chart) << 1) |
                                (p.wrapped[k] ? 1u : 0u);
      const auto [it, inserted] =
          corner_of_key.try_emplace(key, static_cast<std::uint32_t>(atlas.corners.size()));
      if (inserted) {
        atlas.corners.push_back({welded, p.chart, p.wrapped[k]});
        atlas.uvs.push_back(p.uv[k]);
      }
      atlas.indices.push_back(it->second);
    }
  }
  return atlas;
}

}  // namespace sweepd::mannequin
