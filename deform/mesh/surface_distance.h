// Surface distance: for every vertex of a triangle mesh, the length of the shortest path along
// the mesh's edges (Dijkstra) to the nearest vertex of a source set. Binding uses it for the
// neck's hand-over to the head, which grows with the distance from where the head's skin
// weight starts, and to keep any hand-over to skinning from rising too steeply
// (deform/blending/sweep_blending.h).
// Inputs:  adjacency  the mesh's vertex adjacency with edge lengths, n vertices
//                     (vertex_adjacency.h; weld UV-seam copies first: seams cut paths);
//          is_source  n flags.
// Output:  n distances in the positions' unit: 0 at sources, +infinity where none is reachable.
// Throws std::invalid_argument when is_source does not have one flag per vertex.
#pragma once

#include <span>
#include <vector>

#include "deform/mesh/vertex_adjacency.h"

namespace sweepd::deform {

std::vector<float> distance_along_edges(const VertexAdjacency& adjacency,
                                        const std::vector<bool>& is_source);

// The same from sources that start at a distance: per vertex, the least start[u] plus the
// path length from u over every vertex u (start: n values, +infinity where u is no source;
// a vertex's own start counts as a path of length 0).
std::vector<float> distance_along_edges(const VertexAdjacency& adjacency,
                                        std::span<const float> start);

}  // namespace sweepd::deform
