// Shoulders and hips with the limbs down and up (issue 17): sweep against LBS and DQS on the
// mannequin, the shared male and the RiggedFigure, each also mirrored (left and right swapped)
// and rescaled, so that nothing is tuned to one body.
//
// The poses, from the rest pose, every other joint at rest:
// - arm abduction α: each upper arm's joint (RigMap ArmJoints::upper) turned by the shortest arc
//   that points its link (shoulder → elbow) α from the body's down axis towards its own side, in
//   the frontal plane (down, left): α = 0 hangs the arm along the body, 90 holds it level, 150
//   raises it 60° above level, 180 is overhead. The forearm keeps its rest turn against the
//   upper arm;
// - thigh raised β: each thigh's joint (LegJoints::upper) turned the same way towards the body's
//   front (down, forward): β = 90 holds the thigh level, as in sitting.
// The figures, per method, the worse of left and right:
// - ring crease: the largest dihedral change from rest over the edges within 0.6 of the first
//   link's length of the shoulder (hip) joint at rest (CreaseMeter::largest_dihedral_change_near):
//   a hump or a collapse shows as a fold line there;
// - smallest ring section: the loop around the shoulder (hip) joint cut by the plane through it
//   halfway between the link that leads to the joint (clavicle, pelvis) and the first link, posed
//   over rest: below 1 the ring collapses, above 1 it swells;
// - the largest edge stretch anywhere (QualityMeter).
// Asserted: no bind adds a crease at rest; the mirrored and rescaled bodies measure as the body;
// the sweep's ring crease is below LBS's and DQS's where it is (listed at each test, with the
// cases where it is not and why). The sections differ between methods by at most 0.006 with
// the arms at 0 and 45; from 90 up the plane also cuts the chest or the other side of the body
// and the figures (0.01-1.2) say more about where it cuts than about the skin: not asserted.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>

#include "deform/model/forward_kinematics.h"
#include "mannequin/mannequin.h"
#include "metrics/crease_metrics.h"
#include "metrics/quality_metrics.h"
#include "tests/deform/posed_section.h"
#include "tests/deform/shared_male.h"
#include "tests/mirrored_model.h"
#include "tests/rescaled_model.h"

namespace sweepd::metrics::shoulder_hip_test {

using namespace deform;
namespace {

namespace fs = std::filesystem;

using test_models::mirrored;
using test_models::rescaled;

glm::vec3 position(std::span<const glm::mat4> world, int joint) {
  return glm::vec3(world[joint][3]);
}

// `joint` turned by the shortest arc that points its link to `next` `degrees` from `down`
// towards `towards`.
void raise_link(const Skeleton& skeleton, std::span<const glm::mat4> world_rest, Pose& pose,
                int joint, int next, glm::vec3 down, glm::vec3 towards, float degrees) {
  const float a = glm::radians(degrees);
  const glm::vec3 link = glm::normalize(position(world_rest, next) - position(world_rest, joint));
  const glm::vec3 target = std::cos(a) * down + std::sin(a) * towards;
  const glm::vec3 axis = glm::cross(link, target);
  if (glm::length(axis) < 1e-6f) return;  // already pointing there
  turn_joint(skeleton, pose, joint, axis,
             glm::degrees(std::atan2(glm::length(axis), glm::dot(link, target))));
}

struct Limb {
  int joint, next;  // the first link: shoulder → elbow, hip → knee
};

struct Case {
  std::string name;
  bool arms;  // else thighs
  float degrees;
};

const Case kCases[] = {{"arms 0", true, 0.0f},          {"arms 45", true, 45.0f},
                       {"arms 90", true, 90.0f},        {"arms 150", true, 150.0f},
                       {"arms overhead", true, 180.0f}, {"thighs 90", false, 90.0f}};

struct Figures {
  double crease = 0.0;                 // degrees, the worse side
  double smallest_section = 1e9;       // posed / rest, the worse side
  double side_crease[2] = {0.0, 0.0};  // left, right
  double stretch = 0.0;                // the largest edge stretch anywhere, l / l_rest - 1
};

// One model bound and measured under every case and method.
class LimbRoots {
 public:
  explicit LimbRoots(const Model& model)
      : bound_(bind(model, detect_rig_map(model.skeleton))),
        posing_(bound_),
        crease_(bound_),
        quality_(bound_),
        mesh_(bound_.model),
        world_rest_(bound_.model.skeleton.world_rest_matrices()),
        axes_(rest_body_axes(bound_.rig, world_rest_)) {}

  Pose pose(const Case& c) const {
    Pose pose = rest_pose(bound_.model.skeleton);
    const float sides[2] = {1.0f, -1.0f};
    for (int side = 0; side < 2; ++side) {
      const Limb limb = limbs(c.arms)[side];
      const glm::vec3 towards = c.arms ? sides[side] * axes_.left : axes_.forward;
      raise_link(bound_.model.skeleton, world_rest_, pose, limb.joint, limb.next, -axes_.up,
                 towards, c.degrees);
    }
    return pose;
  }

  Figures measure(const Case& c, DeformMethod method) {
    Pose posed = pose(c);
    const std::vector<glm::vec3> positions = test::deformed(posing_, posed, method);
    std::vector<glm::mat4> world(bound_.model.skeleton.size());
    forward_kinematics(bound_.model.skeleton, posed, world);
    Figures f;
    f.stretch = quality_.largest_edge_stretch(positions);
    for (int side = 0; side < 2; ++side) {
      const Limb limb = limbs(c.arms)[side];
      const glm::vec3 root = position(world_rest_, limb.joint);
      const float length = glm::distance(root, position(world_rest_, limb.next));
      f.side_crease[side] = crease_.largest_dihedral_change_near(positions, root, 0.6f * length);
      f.crease = std::max(f.crease, f.side_crease[side]);
      const float rest_area =
          mesh_.section_area(bound_.model.positions, root, bisector(world_rest_, limb));
      const float area =
          mesh_.section_area(positions, position(world, limb.joint), bisector(world, limb));
      if (rest_area > 0.0f)
        f.smallest_section = std::min<double>(f.smallest_section, area / rest_area);
    }
    return f;
  }

 private:
  // The normal of the plane halfway between the limb's first link and the link that leads to
  // it (from the nearest ancestor not at the joint itself): the joint's own section plane.
  glm::vec3 bisector(std::span<const glm::mat4> world, const Limb& limb) const {
    const glm::vec3 at = position(world, limb.joint);
    int before = bound_.model.skeleton.joints[limb.joint].parent;
    while (before >= 0 && glm::distance(position(world, before), at) <
                              1e-3f * glm::distance(at, position(world, limb.next)))
      before = bound_.model.skeleton.joints[before].parent;
    const glm::vec3 lower = glm::normalize(position(world, limb.next) - at);
    if (before < 0) return lower;
    return glm::normalize(glm::normalize(at - position(world, before)) + lower);
  }

  std::array<Limb, 2> limbs(bool arms) const {
    const RigMap& rig = bound_.rig;
    if (arms)
      return {Limb{rig.left_arm.upper, rig.left_arm.lower},
              Limb{rig.right_arm.upper, rig.right_arm.lower}};
    return {Limb{rig.left_leg.upper, rig.left_leg.lower},
            Limb{rig.right_leg.upper, rig.right_leg.lower}};
  }

  BoundModel bound_;
  test::Posing posing_;
  CreaseMeter crease_;
  QualityMeter quality_;
  test::WeldedMesh mesh_;
  std::vector<glm::mat4> world_rest_;
  BodyAxes axes_;
};

struct Body {
  std::string name;
  Model model;
};

std::vector<Body> bodies_of(const std::string& name, const Model& model) {
  return {{name, model},
          {name + " mirrored", mirrored(model)},
          {name + " x0.6", rescaled(model, 0.6f)}};
}

const DeformMethod kMethods[] = {DeformMethod::kSweep, DeformMethod::kLbs, DeformMethod::kDqs};

// Every case's figures, [case][method], printed as a table.
std::vector<std::array<Figures, 3>> measure_all(const Body& body) {
  LimbRoots roots(body.model);
  std::vector<std::array<Figures, 3>> all;
  for (const Case& c : kCases) {
    std::array<Figures, 3>& f = all.emplace_back();
    for (int m = 0; m < 3; ++m) f[m] = roots.measure(c, kMethods[m]);
    std::printf(
        "%-16s %-13s crease sweep %5.1f (L %5.1f R %5.1f) lbs %5.1f dqs %5.1f | section sweep "
        "%.3f lbs %.3f dqs %.3f | stretch sweep %3.0f%% lbs %3.0f%% dqs %3.0f%%\n",
        body.name.c_str(), c.name.c_str(), f[0].crease, f[0].side_crease[0], f[0].side_crease[1],
        f[1].crease, f[2].crease, f[0].smallest_section, f[1].smallest_section,
        f[2].smallest_section, 100 * f[0].stretch, 100 * f[1].stretch, 100 * f[2].stretch);
  }
  return all;
}

// The mirrored and the rescaled body measure as the body itself: nothing in the method depends
// on which side is left or on the body's size. Tolerances: the mirrored body's sides swap, so
// its worse side is the same edge (measured equal to 0.1°); 0.6x scales every length alike, up
// to float rounding in the bind (measured within 0.1°).
void expect_variants_alike(const std::vector<Body>& bodies) {
  const auto original = measure_all(bodies[0]);
  for (std::size_t b = 1; b < bodies.size(); ++b) {
    const auto variant = measure_all(bodies[b]);
    for (std::size_t c = 0; c < original.size(); ++c)
      for (int m = 0; m < 3; ++m) {
        EXPECT_NEAR(variant[c][m].crease, original[c][m].crease, 1.0)
            << bodies[b].name << " " << kCases[c].name << " method " << m;
        EXPECT_NEAR(variant[c][m].smallest_section, original[c][m].smallest_section, 0.01)
            << bodies[b].name << " " << kCases[c].name << " method " << m;
      }
  }
}

// Sweep's ring crease below both baselines' in the named cases.
void expect_sweep_below_baselines(const Body& body, std::initializer_list<std::string> cases) {
  const auto all = measure_all(body);
  for (const std::string& name : cases)
    for (std::size_t c = 0; c < all.size(); ++c) {
      if (kCases[c].name != name) continue;
      EXPECT_LT(all[c][0].crease, all[c][1].crease) << body.name << " " << name << ": lbs";
      EXPECT_LT(all[c][0].crease, all[c][2].crease) << body.name << " " << name << ": dqs";
    }
}

// At rest every method reproduces the mesh: no dihedral angle of any bound model, its mirror
// or its 0.6x copy moves by more than float rounding turns the smallest triangles (the
// mannequin's: 0.055°), so the binding adds no crease of its own.
void expect_no_crease_at_rest(const std::vector<Body>& bodies) {
  for (const Body& body : bodies) {
    const BoundModel bound = bind(body.model, detect_rig_map(body.model.skeleton));
    test::Posing posing(bound);
    const CreaseMeter crease(bound);
    for (DeformMethod method : kMethods) {
      const std::vector<glm::vec3> positions =
          test::deformed(posing, rest_pose(bound.model.skeleton), method);
      const double worst = crease.largest_dihedral_change_near(  // every edge, skinned too
          positions, glm::vec3(0.0f), std::numeric_limits<float>::infinity());
      std::printf("%-16s at rest, %s: largest dihedral change %.3f deg\n", body.name.c_str(),
                  to_string(method), worst);
      EXPECT_LT(worst, 0.2) << body.name << " " << to_string(method);
    }
  }
}

Model rigged_figure() {
  return io::load_gltf(fs::path(SWEEPD_SHARED_DATA) / "models/RiggedFigure/RiggedFigure.gltf");
}

bool rigged_figure_present() {
  return fs::exists(fs::path(SWEEPD_SHARED_DATA) / "models/RiggedFigure/RiggedFigure.gltf");
}

TEST(ShoulderHip, NoBindAddsACreaseAtRest) {
  expect_no_crease_at_rest(bodies_of("mannequin", mannequin::make_mannequin({})));
  if (test::shared_male()) expect_no_crease_at_rest(bodies_of("male", test::shared_male()->model));
  if (rigged_figure_present()) expect_no_crease_at_rest(bodies_of("figure", rigged_figure()));
}

// Measured (degrees, sweep / LBS / DQS): arms 0 45.3 / 68.4 / 62.6, arms 45 3.2 / 6.4 / 6.2,
// arms 90 19.8 / 29.6 / 36.1, arms 150 123.9 / 175.6 / 174.7, overhead 168.4 / 178.5 / 180.0.
// Thighs 90 166.9 / 178.7 / 168.2 is below both by 1.3°, the skin behind the raised thigh
// folding through itself in every method: not asserted. Before the shoulder joint moved out
// from 17.5 to 20 cm (the hanging arm went 4 cm into the chest, which the sweep kept whole and
// folded the armpit through itself) arms 0 measured 175.8 / 57.2 / 69.1 and arms 90 37.4 /
// 35.5 / 42.1.
TEST(ShoulderHip, MannequinSweepBelowBaselines) {
  expect_sweep_below_baselines({"mannequin", mannequin::make_mannequin({})},
                               {"arms 0", "arms 45", "arms 90", "arms 150", "arms overhead"});
}

// The product's other sizes, the four arm cases. Measured at 3k: 79.5 / 99.1 / 88.7, 5.3 /
// 6.3 / 6.2, 26.1 / 29.3 / 31.9, 61.6 / 145.7 / 170.9; at 8k: 76.2 / 99.8 / 78.5, 4.1 / 4.9 /
// 4.8, 18.9 / 22.9 / 26.4, 67.2 / 176.6 / 179.8; at 72k: 34.6 / 61.2 / 50.3, 5.0 / 6.2 / 6.3,
// 29.7 / 34.1 / 41.3, 145.2 / 176.5 / 178.8. At 72k the sweep was below both at 150° only (0:
// 53.6, 45: 8.7, 90: 47.1, its worst edges in the armpit's fillet) until the share smoothing's
// passes grew with the mesh's fineness (deform/blending/sweep_blending.cpp): 150 passes had
// spread the arm's share over half the skin they spread it over on the 20k mesh.
TEST(ShoulderHip, MannequinSweepBelowBaselinesAtOtherSizes) {
  for (int vertices : {3000, 8000, 72000})
    expect_sweep_below_baselines({std::to_string(vertices) + " mannequin",
                                  mannequin::make_mannequin({.target_vertices = vertices})},
                                 {"arms 0", "arms 45", "arms 90", "arms 150"});
}

// Measured: arms 0 43.1 / 174.4 / 178.9, arms 45 9.0 / 10.7 / 11.1, arms 150 88.2 / 129.3 /
// 101.0. Not below: arms 90 51.5 / 51.5 / 64.0 (the worst edge is on the side of the neck, 10 cm
// above the shoulder joint, which the sweeps leave wholly to the model's skinning: above the
// torso's chest key, outside the arm's transition; LBS moves it alike), overhead 144.7 / 177.3
// / 119.5 and thighs 90 179.4 / 146.6 / 160.1.
TEST(ShoulderHip, SharedMaleSweepBelowBaselines) {
  REQUIRE_SHARED_MALE();
  expect_sweep_below_baselines({"male", male.model}, {"arms 0", "arms 45", "arms 150"});
}

TEST(ShoulderHip, MirroredAndRescaledBodiesMeasureAlike) {
  expect_variants_alike(bodies_of("mannequin", mannequin::make_mannequin({})));
  if (test::shared_male()) expect_variants_alike(bodies_of("male", test::shared_male()->model));
  if (rigged_figure_present()) expect_variants_alike(bodies_of("figure", rigged_figure()));
}

}  // namespace
}  // namespace sweepd::metrics::shoulder_hip_test
