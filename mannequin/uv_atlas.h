// The mannequin's UV atlas: one chart per body part, unrolled from the part's axis (angle
// around it across, position along it up), each in its own tile of a square atlas; and one
// tile of loose triangles for the few that no part's chart holds without folding or overlap
// (near the caps' poles and where parts meet: the crotch, the thumbs, the hands, the feet),
// each laid out flat on its own. So no UV triangle folds (every triangle has the orientation
// of the others, counter-clockwise in UV seen from outside) and no two overlap: a position
// map's texel belongs to one surface point.
//
// Inputs:  body       the implicit body whose parts give the charts
//          positions  #W welded vertex positions (on the body's surface)
//          indices    #F*3 triangles on them, counter-clockwise seen from outside
//          owner      #W each vertex's part (the one it is most inside)
// Output:  UvAtlas: the model's vertices as (welded vertex, chart) corners with their UVs in
//          [0, 1]^2, and the same triangles on them; a welded vertex is stored once per chart
//          that uses it (and per side of a chart's cylinder seam), once per loose triangle.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "mannequin/body_shape.h"

namespace sweepd::mannequin {

struct ChartCorner {
  std::uint32_t welded;
  int chart;     // a part's index, or body.part_count() for the loose tile
  bool wrapped;  // the copy right of the part's cylinder seam (u + 1 before packing)
};

struct UvAtlas {
  std::vector<ChartCorner> corners;
  std::vector<glm::vec2> uvs;          // one per corner
  std::vector<std::uint32_t> indices;  // the input triangles on corners, in input order
  std::size_t loose_triangles = 0;
};

UvAtlas make_uv_atlas(const BodyShape& body, std::span<const glm::vec3> positions,
                      std::span<const std::uint32_t> indices, std::span<const int> owner);

}  // namespace sweepd::mannequin
