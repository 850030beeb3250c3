// Collision features on the shared male (paper §4.3): collision regions, self-intersections at
// an elbow and a knee flexed 150° (the angle between their links), skin folding removing them, and
// bone proxies pushing the skin out of the olecranon and the patella.
#include "deform/features/collision_features.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <glm/gtc/quaternion.hpp>

#include "deform/binding/bind.h"
#include "deform/features/bone_proxy.h"
#include "deform/features/collision_regions.h"
#include "deform/features/self_intersection.h"
#include "deform/features/skin_folding.h"
#include "deform/job/deform_job.h"
#include "deform/mesh/enclosed_volume.h"
#include "deform/rig/rig_map.h"
#include "io/bvh/bvh_load.h"
#include "io/gltf/gltf_load.h"
#include "mannequin/mannequin.h"
#include "motion/retarget.h"
#include "tests/deform/shared_male.h"

namespace sweepd::deform {
namespace {

namespace fs = std::filesystem;

struct Fixture {
  BoundModel bound;
  CollisionRegions regions;
};

const Fixture* male() {
  static const Fixture* fixture = []() -> const Fixture* {
    const fs::path file = fs::path(SWEEPD_SHARED_DATA) / "models/makehuman_male_cmu.glb";
    if (!fs::exists(file)) return nullptr;
    auto* f = new Fixture;
    const Model model = io::load_gltf(file);
    f->bound = bind(model, detect_rig_map(model.skeleton));
    f->regions = find_collision_regions(f->bound);
    return f;
  }();
  return fixture;
}

#define REQUIRE_MALE()                                                       \
  if (!male()) GTEST_SKIP() << "shared data absent: makehuman_male_cmu.glb"; \
  const Fixture& fx = *male()

const CollisionRegion& region_at(const CollisionRegions& regions, CollisionSite site) {
  for (const CollisionRegion& r : regions.regions) {
    if (r.site == site) return r;
  }
  throw std::runtime_error(std::string("no region at ") + to_string(site));
}

std::vector<glm::vec3> posed(test::Posing& deformer, float degrees) {
  std::vector<glm::vec3> positions(deformer.bound().model.vertex_count());
  Pose pose = test::left_elbow_and_knee_flexed(deformer.bound().model, degrees);
  deformer.deform(pose, DeformMethod::kSweep, positions, {});
  return positions;
}

// -1 / +1: every corner of triangle t lies before / past the joint; 0 otherwise (a crease
// triangle with corners on both sides, or one at the region's border).
int triangle_side(const CollisionRegions& regions, const CollisionRegion& region, std::uint32_t t) {
  int sum = 0;
  for (int k = 0; k < 3; ++k) {
    const std::uint32_t v = regions.welded_indices[3 * t + k];
    const auto it = std::lower_bound(region.vertices.begin(), region.vertices.end(), v);
    if (it == region.vertices.end() || *it != v) return 0;
    sum += region.sides[it - region.vertices.begin()];
  }
  return sum == 3 ? 1 : (sum == -3 ? -1 : 0);
}

// Pairs where skin from before the joint crosses skin from past it.
int skin_through_skin(const CollisionRegions& regions, const CollisionRegion& region,
                      const std::vector<TrianglePair>& pairs) {
  int count = 0;
  for (const TrianglePair& p : pairs) {
    count += triangle_side(regions, region, p.first) * triangle_side(regions, region, p.second) < 0;
  }
  return count;
}

TEST(CollisionFeatures, RegionsSurroundElbowsKneesShouldersAndHips) {
  REQUIRE_MALE();
  ASSERT_EQ(fx.regions.regions.size(), 8u);
  const Model& model = fx.bound.model;
  const std::vector<glm::mat4> world_rest = model.skeleton.world_rest_matrices();
  for (const CollisionRegion& region : fx.regions.regions) {
    SCOPED_TRACE(to_string(region.site));
    ASSERT_EQ(region.sides.size(), region.vertices.size());
    const auto before = std::count(region.sides.begin(), region.sides.end(), -1);
    EXPECT_GT(before, 0);
    EXPECT_LT(before, static_cast<long>(region.vertices.size()));
    // Around its joint: the vertices' centroid within 12 cm of it (limbs are ~10 cm thick).
    glm::vec3 centroid(0.0f);
    for (std::uint32_t v : region.vertices) centroid += model.positions[v];
    centroid /= static_cast<float>(region.vertices.size());
    EXPECT_LT(glm::distance(centroid, glm::vec3(world_rest[region.joint][3])), 0.12f);
    // Every triangle touching a region vertex is listed (folding's volume relies on it).
    std::size_t touching = 0;
    for (std::uint32_t t = 0; t < model.triangle_count(); ++t) {
      for (int k = 0; k < 3; ++k) {
        if (std::binary_search(region.vertices.begin(), region.vertices.end(),
                               fx.regions.welded_indices[3 * t + k])) {
          ++touching;
          break;
        }
      }
    }
    EXPECT_EQ(region.triangles.size(), touching);
  }
  // The male is left-right symmetric: mirrored regions match in size within 5 %.
  for (auto [left, right] : {std::pair{CollisionSite::kLeftElbow, CollisionSite::kRightElbow},
                             std::pair{CollisionSite::kLeftKnee, CollisionSite::kRightKnee},
                             std::pair{CollisionSite::kLeftShoulder, CollisionSite::kRightShoulder},
                             std::pair{CollisionSite::kLeftHip, CollisionSite::kRightHip}}) {
    const float l = region_at(fx.regions, left).vertices.size();
    const float r = region_at(fx.regions, right).vertices.size();
    EXPECT_NEAR(l / r, 1.0f, 0.05f) << to_string(left);
  }
}

TEST(CollisionFeatures, RestPoseHasNoSelfIntersections) {
  REQUIRE_MALE();
  SelfIntersectionDetector detector;
  std::vector<TrianglePair> pairs;
  for (const CollisionRegion& region : fx.regions.regions) {
    detector.detect(fx.bound.model.positions, fx.regions.welded_indices, region.triangles, pairs);
    EXPECT_TRUE(pairs.empty()) << to_string(region.site) << ": " << pairs.size() << " pairs";
  }
}

// The largest edge stretch (posed over rest length) over a region's triangles.
float largest_stretch(const CollisionRegions& regions, const CollisionRegion& region,
                      const std::vector<glm::vec3>& positions) {
  float largest = 0.0f;
  for (std::size_t i = 0; i < region.triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t* corner = &regions.welded_indices[3 * region.triangles[i]];
      largest =
          std::max(largest, glm::distance(positions[corner[k]], positions[corner[(k + 1) % 3]]) /
                                region.rest_edges[3 * i + k]);
    }
  return largest;
}

TEST(CollisionFeatures, FoldingRemovesSkinThroughSkinAtBentElbowAndKnee) {
  REQUIRE_MALE();
  test::Posing deformer(fx.bound);
  SelfIntersectionDetector detector;
  SkinFolder folder;
  std::vector<TrianglePair> pairs;
  // 140° and 150°: with one link key per link (bind's default since stop 65) the sweep alone
  // barely crosses itself at 135° (2 skin-through-skin pairs at the elbow, none at the knee; 52
  // and 48 with two), leaving nothing to fold there.
  for (float degrees : {140.0f, 150.0f}) {
    std::vector<glm::vec3> positions = posed(deformer, degrees);
    for (CollisionSite site : {CollisionSite::kLeftElbow, CollisionSite::kLeftKnee}) {
      SCOPED_TRACE(std::string(to_string(site)) + " at " + std::to_string(degrees));
      const CollisionRegion& region = region_at(fx.regions, site);
      detector.detect(positions, fx.regions.welded_indices, region.triangles, pairs);
      const std::size_t before = pairs.size();
      const int crossing_before = skin_through_skin(fx.regions, region, pairs);
      const float stretch_before = largest_stretch(fx.regions, region, positions);
      const FoldingResult result =
          folder.fold(region, fx.regions.welded_indices, pairs, 5e-4f, positions);
      detector.detect(positions, fx.regions.welded_indices, region.triangles, pairs);
      std::printf(
          "%s %.0f°: %zu pairs (%d skin through skin) -> %zu after folding (%d); "
          "%d groups (%d eased, %d refused), %d vertices pulled back, deepest %.1f mm, volume "
          "%+.1f cm³, largest edge stretch %.2fx -> %.2fx\n",
          to_string(site), degrees, before, crossing_before, pairs.size(),
          skin_through_skin(fx.regions, region, pairs), result.groups, result.eased, result.refused,
          result.moved, result.max_depth * 1e3f, result.volume_change * 1e6, stretch_before,
          largest_stretch(fx.regions, region, positions));
      // One call pulls back as far as the skin allows (a fold that would stretch an edge past
      // kMostFoldStretch times its rest length is eased or refused): fewer crossings, not none
      // (measured 37 -> 0, 28 -> 0, 65 -> 40, 58 -> 0; at 160° one call leaves the elbow with
      // more, 51 -> 56, which is why the rounds below keep no round that adds pairs); the rounds
      // below clear them.
      EXPECT_GT(crossing_before, 0);
      EXPECT_LT(skin_through_skin(fx.regions, region, pairs), crossing_before);
      // No tear: no edge past kMostFoldStretch times its rest length that was not already
      // (float rounding of the lengths: 1e-5).
      EXPECT_LE(largest_stretch(fx.regions, region, positions),
                std::max(kMostFoldStretch, stretch_before) * (1.0f + 1e-5f));
      EXPECT_GT(result.moved, 0);
      // Pulling skin back behind the plane removes the doubly covered volume.
      EXPECT_LT(result.volume_change, 0.0);
    }
    // The right arm and leg are not bent: nothing to fold there.
    for (CollisionSite site : {CollisionSite::kRightElbow, CollisionSite::kRightKnee}) {
      detector.detect(positions, fx.regions.welded_indices, region_at(fx.regions, site).triangles,
                      pairs);
      EXPECT_TRUE(pairs.empty()) << to_string(site);
    }
  }
}

// Intersecting pairs of one region.
int pairs_at(const CollisionRegions& regions, const CollisionRegion& region,
             const std::vector<glm::vec3>& positions) {
  SelfIntersectionDetector detector;
  std::vector<TrianglePair> pairs;
  detector.detect(positions, regions.welded_indices, region.triangles, pairs);
  return static_cast<int>(pairs.size());
}

TEST(CollisionFeatures, FoldingRoundsClearTheElbowAndKneeAt150) {
  REQUIRE_MALE();
  test::Posing deformer(fx.bound);
  CollisionFeatureOptions options;
  options.protrusion = false;
  CollisionFeatures features(deformer.runtime.collision(), options);
  for (float degrees : {120.0f, 135.0f, 150.0f, 160.0f}) {
    std::vector<glm::vec3> positions = posed(deformer, degrees);
    const std::vector<glm::vec3> unfolded = positions;
    const FeatureReport report = features.apply(deformer.skinning(), positions);
    int after_total = 0;
    for (const CollisionRegion& region : fx.regions.regions) {
      SCOPED_TRACE(std::string(to_string(region.site)) + " at " + std::to_string(degrees));
      const int before = pairs_at(fx.regions, region, unfolded);
      const int after = pairs_at(fx.regions, region, positions);
      after_total += after;
      if (before > 0)
        std::printf("%s %.0f°: %d pairs -> %d after folding rounds\n", to_string(region.site),
                    degrees, before, after);
      EXPECT_LE(after, before) << "a round that adds pairs is never kept";
      EXPECT_LE(largest_stretch(fx.regions, region, positions),
                std::max(kMostFoldStretch, largest_stretch(fx.regions, region, unfolded)) *
                    (1.0f + 1e-5f))
          << "a round that tears the skin is never kept";
      const bool bent =
          region.site == CollisionSite::kLeftElbow || region.site == CollisionSite::kLeftKnee;
      if (bent && degrees == 150.0f) {  // the acceptance: some before, none after
        EXPECT_GT(before, 0);
        EXPECT_EQ(after, 0);
      }
    }
    EXPECT_EQ(report.pairs_after, after_total);
  }
}

TEST(CollisionFeatures, BoneProxiesAreClosedAndMoveWithTheirBone) {
  REQUIRE_MALE();
  const std::vector<BoneProxy> proxies = make_bone_proxies(fx.bound, fx.regions);
  ASSERT_EQ(proxies.size(), 4u);  // two olecranons, two patellae
  test::Posing deformer(fx.bound);
  const std::vector<glm::vec3> positions = posed(deformer, 150.0f);
  for (const BoneProxy& proxy : proxies) {
    SCOPED_TRACE(to_string(proxy.site));
    ASSERT_EQ(proxy.rest_positions.size(), 42u);
    std::vector<std::uint32_t> all(proxy.indices.size() / 3);
    for (std::uint32_t t = 0; t < all.size(); ++t) all[t] = t;
    // Closed and outward: positive volume, and a 42-vertex icosphere inscribed in the ellipsoid
    // holds between 80 % and 100 % of it.
    float radius = 0.0f;
    for (const glm::vec3& p : proxy.rest_positions) {
      radius = std::max(radius, glm::distance(p, proxy.rest_centre) / 1.5f);
    }
    const double ellipsoid = 4.0 / 3.0 * M_PI * radius * radius * 1.5 * radius;
    const double volume = enclosed_volume(proxy.rest_positions, proxy.indices, all);
    EXPECT_GT(volume, 0.8 * ellipsoid);
    EXPECT_LT(volume, 1.0 * ellipsoid);
    // Rigid with its bone: distances to the bone's joint are kept (float round-off, 1e-5 m).
    std::vector<glm::vec3> moved(proxy.rest_positions.size());
    const glm::vec3 anchor = pose_bone_proxy(proxy, deformer.skinning(), moved);
    const glm::vec3 rest_joint =
        glm::vec3(fx.bound.model.skeleton.world_rest_matrices()[proxy.joint][3]);
    const glm::vec3 posed_joint = glm::vec3(deformer.world_pose()[proxy.joint][3]);
    EXPECT_NEAR(glm::distance(anchor, posed_joint), glm::distance(proxy.rest_anchor, rest_joint),
                1e-5f);
    for (std::size_t i = 0; i < moved.size(); ++i) {
      EXPECT_NEAR(glm::distance(moved[i], anchor),
                  glm::distance(proxy.rest_positions[i], proxy.rest_anchor), 1e-5f);
    }
    // At rest no skin vertex of its region is inside it.
    int inside = 0;
    for (std::uint32_t v : fx.regions.regions[proxy.region].vertices) {
      inside += penetration_depth(proxy.rest_positions, proxy.indices, proxy.rest_anchor,
                                  fx.bound.model.positions[v]) > 0.0f;
    }
    EXPECT_EQ(inside, 0) << "rest skin inside the proxy";
    (void)positions;
  }
}

// Skin vertices of each proxy's region inside the posed proxy.
int skin_inside(const BoneProxy& proxy, std::span<const glm::mat4> skinning,
                const CollisionRegions& regions, const std::vector<glm::vec3>& positions) {
  std::vector<glm::vec3> moved(proxy.rest_positions.size());
  const glm::vec3 anchor = pose_bone_proxy(proxy, skinning, moved);
  int inside = 0;
  for (std::uint32_t v : regions.regions[proxy.region].vertices)
    inside += penetration_depth(moved, proxy.indices, anchor, positions[v]) > 0.0f;
  return inside;
}

TEST(CollisionFeatures, BentElbowAndKneeReachTheirProxiesAndProtrusionPushesTheSkinOut) {
  REQUIRE_MALE();
  test::Posing deformer(fx.bound);
  const std::vector<BoneProxy> proxies = make_bone_proxies(fx.bound, fx.regions);
  // Protrusion works on any posed skin; LBS's collapsing elbow and knee tips do reach the bone,
  // while the sweep's mitred joint keys (deform/posing/key_posing.h) keep the tip's skin over it.
  for (DeformMethod method : {DeformMethod::kSweep, DeformMethod::kLbs}) {
    std::vector<glm::vec3> positions(fx.bound.model.vertex_count());
    Pose pose = test::left_elbow_and_knee_flexed(fx.bound.model, 150.0f);
    deformer.deform(pose, method, positions, {});
    for (const BoneProxy& proxy : proxies) {
      SCOPED_TRACE(std::string(to_string(proxy.site)) + " " + to_string(method));
      const int before = skin_inside(proxy, deformer.skinning(), fx.regions, positions);
      std::vector<glm::vec3> moved(proxy.rest_positions.size());
      const glm::vec3 anchor = pose_bone_proxy(proxy, deformer.skinning(), moved);
      const ProtrusionResult result =
          push_out_of_bone_proxy(moved, proxy.indices, anchor, fx.regions.regions[proxy.region],
                                 fx.regions.welded_indices, 2e-4f, positions);
      const int after = skin_inside(proxy, deformer.skinning(), fx.regions, positions);
      std::printf(
          "%s, %s proxy at 150°: %d skin vertices inside -> %d; deepest %.1f mm, volume %+.2f "
          "cm³\n",
          to_string(method), to_string(proxy.site), before, after, result.max_depth * 1e3f,
          result.volume_change * 1e6);
      const bool bent =
          proxy.site == CollisionSite::kLeftElbow || proxy.site == CollisionSite::kLeftKnee;
      if (bent && method == DeformMethod::kLbs) {
        // Flexion carries the olecranon / patella into LBS's skin at the tip of the bend.
        EXPECT_GT(before, 0);
        // Pushed outward, away from the bone: the enclosed volume grows.
        EXPECT_GT(result.volume_change, 0.0);
      }
      if (!bent) {
        EXPECT_EQ(before, 0) << "the straight arm and leg keep their proxies under the skin";
      }
      EXPECT_EQ(result.moved, before);
      EXPECT_EQ(after, 0);
    }
  }
}

TEST(CollisionFeatures, OneCallFoldsProtrudesAndKeepsSeamCopiesTogether) {
  REQUIRE_MALE();
  test::Posing deformer(fx.bound);
  std::vector<glm::vec3> positions = posed(deformer, 150.0f);
  const std::vector<glm::vec3> unfolded = positions;
  CollisionFeatures features(deformer.runtime.collision());
  const FeatureReport report = features.apply(deformer.skinning(), positions);
  std::printf(
      "150°: %d pairs -> %d, %d vertices folded (deepest %.1f mm), %d protruded "
      "(deepest %.1f mm), volume %+.1f cm³\n",
      report.pairs_before, report.pairs_after, report.folded, report.deepest_fold * 1e3f,
      report.protruded, report.deepest_protrusion * 1e3f, report.volume_change * 1e6);
  // The same count as detecting region by region on the unfolded mesh.
  SelfIntersectionDetector detector;
  std::vector<TrianglePair> pairs;
  int expected = 0;
  for (const CollisionRegion& region : fx.regions.regions) {
    detector.detect(unfolded, fx.regions.welded_indices, region.triangles, pairs);
    expected += static_cast<int>(pairs.size());
  }
  EXPECT_EQ(report.pairs_before, expected);
  EXPECT_LT(report.pairs_after, report.pairs_before);
  // The volume change, per sweep (I_C of volume preservation), sums to the report's: every
  // region and proxy belongs to its limb's sweep. Summed in another order: 1e-12 of a cm³.
  double by_sweep = 0.0;
  for (const double change : features.sweep_volume_change()) by_sweep += change;
  EXPECT_NEAR(by_sweep, report.volume_change, 1e-18);
  EXPECT_NE(report.volume_change, 0.0);
  EXPECT_GT(report.folded, 0);
  // Protrusion moves exactly the skin that folding alone leaves inside a proxy (none at 150°:
  // the fold pulls the crease off the olecranon; without folding 7 and 4 vertices are inside,
  // BentElbowAndKneeReachTheirProxies...).
  std::vector<glm::vec3> folded_only = unfolded;
  CollisionFeatureOptions fold_options;
  fold_options.protrusion = false;
  CollisionFeatures(deformer.runtime.collision(), fold_options)
      .apply(deformer.skinning(), folded_only);
  int inside_after_folding = 0;
  for (const BoneProxy& proxy : features.proxies())
    inside_after_folding += skin_inside(proxy, deformer.skinning(), fx.regions, folded_only);
  EXPECT_EQ(report.protruded, inside_after_folding);
  // Protrusion runs last: no skin vertex is left inside a proxy.
  for (const BoneProxy& proxy : features.proxies()) {
    EXPECT_EQ(skin_inside(proxy, deformer.skinning(), fx.regions, positions), 0)
        << to_string(proxy.site);
  }
  // UV-seam copies sit exactly on their representative, so the mesh does not tear.
  for (const auto& [copy, representative] : features.regions().seam_copies) {
    ASSERT_EQ(positions[copy], positions[representative]) << "vertex " << copy;
  }
  // Vertices outside every region are untouched.
  std::vector<bool> in_region(positions.size());
  for (const CollisionRegion& region : fx.regions.regions) {
    for (std::uint32_t v : region.vertices) in_region[v] = true;
  }
  for (std::size_t v = 0; v < positions.size(); ++v) {
    if (!in_region[fx.regions.representative[v]]) {
      ASSERT_EQ(positions[v], unfolded[v]) << v;
    }
  }
}

TEST(CollisionFeatures, FoldingNeverAddsPairsOnClipFrames) {
  REQUIRE_MALE();
  const fs::path data = fs::path(SWEEPD_SHARED_DATA);
  test::Posing deformer(fx.bound);
  CollisionFeatureOptions options;
  options.protrusion = false;
  CollisionFeatures features(deformer.runtime.collision(), options);
  // Frames where the male folds: 1257 of cmu_01_01 (both elbows bent furthest), and 4400 of
  // cmu_01_03 (the most region pairs among its every 50th frame). Frame 2000 of cmu_01_03, where
  // one plane fitted across two separate intersecting groups once tripled the pairs, has none
  // since the hip links keep their rest angle to the pelvis (motion/retarget.h).
  for (const auto& [clip, frame] :
       {std::pair{"motion/cmu_01_01.bvh", 1257}, std::pair{"motion/cmu_01_03.bvh", 4400}}) {
    SCOPED_TRACE(std::string(clip) + " frame " + std::to_string(frame));
    const motion::Retargeter retargeter(io::load_bvh(data / clip), fx.bound.model);
    Pose pose = retargeter.pose_at_frame(frame);
    std::vector<glm::vec3> positions(fx.bound.model.vertex_count());
    deformer.deform(pose, DeformMethod::kSweep, positions, {});
    const FeatureReport report = features.apply(deformer.skinning(), positions);
    std::printf("%s frame %d: %d pairs -> %d, %d vertices pulled back\n", clip, frame,
                report.pairs_before, report.pairs_after, report.folded);
    EXPECT_GT(report.pairs_before, 0);
    EXPECT_LE(report.pairs_after, report.pairs_before);
  }
}

// Every feature that moves skin (folding, protrusion, whole-body contact) on every 100th frame
// of both clips, on the male and the 20k mannequin: no edge stretched past 2.5 times its rest
// length (kMostFoldStretch, written out so that raising it fails here) that the sweep did not
// stretch so far already (float rounding: 1e-5).
// Before folding and contact checked for tears, cmu_01_01 frame 1200 (the male's arm hanging
// against his chest) stretched an armpit edge 33.9x, and contact tore the skin up to 94x.
TEST(CollisionFeatures, NoFeatureTearsTheSkinOnClipFrames) {
  REQUIRE_MALE();
  const fs::path data = fs::path(SWEEPD_SHARED_DATA);
  const Model mannequin = mannequin::make_mannequin({.target_vertices = 20000});
  const BoundModel mannequin_bound = bind(mannequin, detect_rig_map(mannequin.skeleton));
  for (const BoundModel* bound : {&fx.bound, &mannequin_bound}) {
    test::Posing sweep(*bound), featured(*bound);
    featured.features = {.folding = true, .protrusion = true, .contact = true};
    const ContactModel& skin = featured.runtime.collision().contact;
    const auto largest_stretch = [&](std::span<const glm::vec3> positions) {
      float largest = 0.0f;
      for (std::uint32_t v = 0; v < skin.adjacency.vertex_count(); ++v)
        for (std::size_t i = 0; i < skin.adjacency.neighbours(v).size(); ++i)
          largest = std::max(
              largest, glm::distance(positions[v], positions[skin.adjacency.neighbours(v)[i]]) /
                           skin.adjacency.lengths(v)[i]);
      return largest;
    };
    float worst_sweep = 0.0f, worst_featured = 0.0f;
    for (const char* clip : {"motion/cmu_01_01.bvh", "motion/cmu_01_03.bvh"}) {
      const motion::Retargeter retargeter(io::load_bvh(data / clip), bound->model);
      std::vector<glm::vec3> plain(bound->model.vertex_count()), moved(plain.size());
      for (int frame = 0; frame < retargeter.frame_count(); frame += 100) {
        SCOPED_TRACE(std::string(clip) + " frame " + std::to_string(frame));
        Pose a = retargeter.pose_at_frame(frame), b = a;
        sweep.deform(a, DeformMethod::kSweep, plain);
        featured.deform(b, DeformMethod::kSweep, moved);
        const float before = largest_stretch(plain), after = largest_stretch(moved);
        EXPECT_LE(after, std::max(2.5f, before) * (1.0f + 1e-5f));
        worst_sweep = std::max(worst_sweep, before);
        worst_featured = std::max(worst_featured, after);
      }
    }
    std::printf(
        "%s, every 100th frame of both clips: largest edge stretch %.2fx, with the "
        "features %.2fx\n",
        bound->model.name.c_str(), worst_sweep, worst_featured);
  }
}

}  // namespace
}  // namespace sweepd::deform
