// Marching tetrahedra: polygonises the zero level set of a scalar field sampled on a regular
// grid into a closed, consistently oriented 2-manifold triangle mesh (negative = inside).
//
// Every cube is split into the same 6 tetrahedra around its main diagonal (Kuhn split), so
// neighbouring cubes agree on their shared faces; samples exactly 0 count as outside and edge
// vertices are shared through their grid edge, so the result has no cracks or T-junctions.
// The grid is walked in blocks of cells; the field evaluates a whole block at once and may
// declare a block empty (entirely outside), which lets it skip space far from the surface.
// The field must be a function of the sample position only (the same value for a point shared
// by two blocks), and positive on the outer layer of grid points for the mesh to be closed.
//
// Inputs:  grid   origin, spacing and cell counts (points = cells + 1 per axis)
//          field  BlockField callback, see below
// Outputs: positions  #V edge crossings (never exactly at a grid point)
//          indices    #F*3 triangles, counter-clockwise seen from outside (positive side)
#pragma once

#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <span>
#include <vector>

namespace sweepd::mannequin {

struct SampleGrid {
  glm::vec3 origin{0.0f};  // position of grid point (0, 0, 0)
  float spacing = 1.0f;    // distance between neighbouring grid points
  glm::ivec3 cells{0};     // cells per axis
  // Position of grid point (i, j, k); computed the same way wherever it is asked for.
  glm::vec3 point(int i, int j, int k) const {
    return origin +
           spacing * glm::vec3(static_cast<float>(i), static_cast<float>(j), static_cast<float>(k));
  }
};

// Fills values[n] for points[n] (a block's grid points, x fastest) and returns true, or
// returns false when the axis-aligned box [lo, hi] holding them is entirely outside.
using BlockField = std::function<bool(const glm::vec3& lo, const glm::vec3& hi,
                                      std::span<const glm::vec3> points, std::span<float> values)>;

struct IsoSurface {
  std::vector<glm::vec3> positions;
  std::vector<std::uint32_t> indices;
};

void marching_tetrahedra(const SampleGrid& grid, const BlockField& field, IsoSurface& surface);

}  // namespace sweepd::mannequin
