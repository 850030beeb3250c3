// The procedural mannequin: a rigged, skinned, UV-mapped human body generated from code, for
// use where no model file is at hand (the daemon's default model, tests, benchmarks).
//
// Output Model (see model.h for its invariants; validate() is empty):
// - one closed, connected 2-manifold surface once the UV-seam duplicates are welded
//   (vertices at chart seams are stored twice, same position and normal, different UV);
// - about options.target_vertices vertices (within 10% from 2k to 300k);
// - 31 joints with the CMU MotionBuilder names of the shared MakeHuman male and the CMU BVH
//   clips (Hips root, ..., LeftHandFinger1, LThumb, ...), parents first, identity rest
//   rotations; A-pose, Y up, facing +Z, feet on y = 0, about 1.75 m tall;
// - smooth skin weights (4 influences, summing to 1); UVs in [0, 1]^2: one chart per body part
//   and one tile of loose triangles, none folded or overlapping another (uv_atlas.h).
// The result depends only on the options: two calls give bit-identical models.
#pragma once

#include "deform/model/model.h"

namespace sweepd::mannequin {

struct MannequinOptions {
  int target_vertices = 20000;  // kMannequinMinVertices .. kMannequinMaxVertices
};

inline constexpr int kMannequinMinVertices = 1000;
inline constexpr int kMannequinMaxVertices = 500000;

// Throws std::invalid_argument (saying which option and why) for options out of range.
deform::Model make_mannequin(const MannequinOptions& options);

}  // namespace sweepd::mannequin
