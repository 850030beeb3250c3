#include "deform/binding/carried_end.h"

#include <limits>

#include "deform/binding/section_key_ellipse.h"
#include "deform/model/joint_paths.h"

namespace sweepd::deform {

namespace {

// Where the walk outward along the axis starts and where it gives up, as fractions of the
// carried extent. On the MakeHuman bodies (elbow to fingertips ~0.40 m, the wrist at ~0.54 of
// it; neck base to crown ~0.31 m, the neck's narrowest at ~0.35, under the jaw) the ends lie
// well inside. The neck's walk starts above the shoulders' cut (0.02-0.05 of the extent cut
// the trapezius, 4-9 times the neck's section).
struct Range {
  float first, last;
};
Range range_of(CarriedEndKind kind) {
  return kind == CarriedEndKind::kHand ? Range{0.25f, 0.85f} : Range{0.08f, 0.60f};
}
// The walk stops where the section widens past kWidening × the narrowest so far (the palm, the
// jaw), or shrinks below kOtherTube × the one before (no longer the limb's tube: the plane
// reached the chin's underside and cut the mouth's inside, 54 -> 3 cm² between two samples).
constexpr float kWidening = 1.1f;
constexpr float kOtherTube = 0.4f;
constexpr int kSamples = 33;

}  // namespace

CarriedEnd find_carried_end(const Model& model, const WeldedMesh& mesh,
                            std::span<const glm::mat4> world_rest, int joint, CarriedEndKind kind) {
  CarriedEnd end;
  const Skeleton& skeleton = model.skeleton;
  const glm::vec3 origin(world_rest[joint][3]);
  std::vector<bool> carries(skeleton.size(), false);
  for (int j = 0; j < skeleton.size(); ++j)
    carries[j] = j == joint || is_strict_ancestor(skeleton, joint, j);
  std::vector<std::size_t> carried;
  glm::dvec3 sum(0.0);
  double total = 0.0;
  for (std::size_t v = 0; v < model.vertex_count(); ++v) {
    float weight = 0.0f;
    for (int k = 0; k < kInfluences; ++k)
      if (carries[model.skin_joints[v][k]]) weight += model.skin_weights[v][k];
    if (weight < 0.5f) continue;
    carried.push_back(v);
    sum += glm::dvec3(model.positions[v] - origin) * static_cast<double>(weight);
    total += weight;
  }
  if (carried.empty() || !(glm::length(sum) > 1e-9 * total)) {
    end.problem = "no vertex is weighted one half or more to '" + skeleton.joints[joint].name +
                  "' away from its joint";
    return end;
  }
  end.axis = glm::normalize(glm::vec3(sum / total));
  float extent = 0.0f;
  for (std::size_t v : carried)
    extent = std::max(extent, glm::dot(model.positions[v] - origin, end.axis));
  const Range range = range_of(kind);
  float least = std::numeric_limits<float>::infinity(), previous = 0.0f;
  for (int i = 0; i < kSamples; ++i) {
    const float fraction =
        range.first + (range.last - range.first) * static_cast<float>(i) / (kSamples - 1);
    const glm::vec3 point = origin + fraction * extent * end.axis;
    const KeyEllipseFit fit = fit_key_ellipse(mesh.positions, mesh.indices,
                                              make_plane_frame(point, end.axis), point);
    // A cut that misses the tube around the axis (between the fingers) says nothing.
    if (!fit.valid || !fit.closed_loop || !fit.encloses_link_point) continue;
    const float area = fit.fit_2d.area;
    if (area > kWidening * least || area < kOtherTube * previous) break;
    previous = area;
    if (!(area < least)) continue;
    least = area;
    end.found = true;
    end.point = point;
    end.fraction = fraction;
    end.section_area = area;
  }
  if (!end.found)
    end.problem = "no plane across '" + skeleton.joints[joint].name +
                  "' cuts a closed section around its axis where the " +
                  (kind == CarriedEndKind::kHand ? "wrist" : "neck's top") + " would be";
  return end;
}

}  // namespace sweepd::deform
