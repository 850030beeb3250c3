// Sweep coordinates of a point (paper §3.3–3.4): which moving ellipse E_t it is bound to, its
// angle θ on it, its displacement from it, and back.
//
// bind_point: the sweep's planes P(t_j) are sampled (SweepPlanes); a point between two
// neighbouring planes gets t_V = (d_{j+1} t_j + d_j t_{j+1}) / (d_j + d_{j+1}) from its distances
// to them. Where the planes cross (a curved torso) several pairs may enclose the point: the one
// whose ellipse centre C̃(t_V) is nearest wins, never a far one. A point before the first plane
// or after the last is bound to the end ellipse (t = 0 or 1); its offset along N is kept in c.
// Then (x, y, c) = R(t_V)^T (V - C̃(t_V)) with C̃ = C + R (o, 0) the ellipse's centre,
// θ_V = atan2(y / b, x / a), and with r = |(x / a, y / b)| the displacement is
// da = (r - 1) a, db = (r - 1) b.
// evaluate_point: V = C̃(t) + R(t) ((a(t) + da) cos θ, (b(t) + db) sin θ, c) — exact at rest.
// The planes P(t) are those through C(t) and C̃(t) alike: o is in the plane.
#pragma once

#include <glm/glm.hpp>
#include <vector>

#include "deform/binding/bound_model.h"
#include "deform/sweep/sweep.h"

namespace sweepd::deform {

struct SweepPlanes {
  std::vector<float> t;           // sample parameters, increasing, t[0] = 0, t.back() = 1
  std::vector<glm::vec3> centre;  // C(t_j)
  std::vector<glm::vec3> normal;  // N(t_j)
};

// samples_per_span >= 1 planes per key span (plus the last one).
SweepPlanes sample_planes(const Sweep& sweep, int samples_per_span);

SweepCoordinate bind_point(const Sweep& sweep, const SweepPlanes& planes, glm::vec3 point);

glm::vec3 evaluate_point(const Sweep& sweep, const SweepCoordinate& coordinate);

}  // namespace sweepd::deform
