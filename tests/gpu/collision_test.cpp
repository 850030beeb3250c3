// GPU collision detection (gpu::CollisionDetector on llvmpipe or a real GPU) against the CPU
// reference: synthetic configurations with known answers, touching and coplanar knife edges,
// near-degenerate pairs the float filter must hand to the exact test, random soups, lists
// batched in one submission and answered again from it, and the shared male's and the
// mannequin's collision regions and whole body, elbow and knee flexed 150°, before and after
// folding (one fold, and the whole detect -> fold/relax feature pass with either detector).
// And whole-body contact on the procedural mannequin: the GPU's pairs over the whole skin equal
// deform::WholeBodyDetector's, and the contact feature moves the same vertices with either.
#include "gpu/collision.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <glm/gtc/quaternion.hpp>
#include <random>

#include "deform/binding/bind.h"
#include "deform/features/collision_features.h"
#include "deform/features/collision_regions.h"
#include "deform/features/skin_folding.h"
#include "deform/features/whole_body_detector.h"
#include "deform/job/deform_job.h"
#include "deform/rig/rig_map.h"
#include "io/gltf/gltf_load.h"
#include "mannequin/mannequin.h"
#include "tests/deform/collision_shapes.h"
#include "tests/deform/shared_male.h"

namespace sweepd::gpu {
namespace {

using deform::TrianglePair;
using deform::testing::SoupMesh;

class CollisionTest : public ::testing::Test {
 protected:
  std::vector<TrianglePair> on_gpu(const SoupMesh& mesh, const std::vector<std::uint32_t>& ids) {
    std::vector<TrianglePair> pairs;
    gpu_.detect(mesh.positions, mesh.indices, ids, pairs);
    return pairs;
  }
  std::vector<TrianglePair> on_cpu(const SoupMesh& mesh, const std::vector<std::uint32_t>& ids) {
    std::vector<TrianglePair> pairs;
    cpu_.detect(mesh.positions, mesh.indices, ids, pairs);
    return pairs;
  }
  void expect_same(const SoupMesh& mesh) {
    const std::vector<std::uint32_t> ids = mesh.all_triangles();
    const std::vector<TrianglePair> cpu = on_cpu(mesh, ids);
    EXPECT_EQ(on_gpu(mesh, ids), cpu);
    EXPECT_EQ(cpu, deform::testing::all_pairs_reference(mesh, ids));
  }

  // Every region and the whole body in one detect_all, then each list alone (answered from that
  // submission), against the CPU reference list by list. Returns the pairs found in all.
  std::size_t expect_regions_and_body_match(std::span<const glm::vec3> positions,
                                            const deform::CollisionRegions& regions) {
    std::vector<std::uint32_t> body(regions.welded_indices.size() / 3);
    for (std::uint32_t t = 0; t < body.size(); ++t) body[t] = t;
    std::vector<std::span<const std::uint32_t>> lists;
    for (const deform::CollisionRegion& region : regions.regions) lists.push_back(region.triangles);
    lists.push_back(body);
    std::vector<std::vector<TrianglePair>> gpu(lists.size());
    gpu_.detect_all(positions, regions.welded_indices, lists, gpu);
    EXPECT_EQ(gpu_.last_stats().submissions, 1);
    EXPECT_EQ(gpu_.last_stats().lists, static_cast<int>(lists.size()));
    std::size_t found = 0;
    std::vector<TrianglePair> cpu, again;
    for (std::size_t l = 0; l < lists.size(); ++l) {
      SCOPED_TRACE(l + 1 < lists.size() ? to_string(regions.regions[l].site) : "whole body");
      cpu_.detect(positions, regions.welded_indices, lists[l], cpu);
      EXPECT_EQ(gpu[l], cpu);
      gpu_.detect(positions, regions.welded_indices, lists[l], again);
      EXPECT_EQ(gpu_.last_stats().submissions, 0) << "unchanged positions: no GPU work";
      EXPECT_EQ(again, cpu);
      found += cpu.size();
    }
    return found;
  }

  Context context_;
  CollisionDetector gpu_{context_};
  deform::SelfIntersectionDetector cpu_;
};

// A model bound, its collision regions, and its vertices posed by the sweep with the left elbow
// and knee flexed 150°.
struct BentModel {
  explicit BentModel(const deform::Model& model)
      : bound(deform::bind(model, deform::detect_rig_map(model.skeleton))),
        regions(deform::find_collision_regions(bound)),
        deformer(bound),
        pose(deform::test::left_elbow_and_knee_flexed(model, 150.0f)),
        positions(model.vertex_count()) {
    deformer.deform(pose, deform::DeformMethod::kSweep, positions, {});
  }
  deform::BoundModel bound;
  deform::CollisionRegions regions;
  deform::test::Posing deformer;
  deform::Pose pose;
  std::vector<glm::vec3> positions;
};

// Adds triangle (p, q, r) with vertices of its own.
void add_triangle(SoupMesh& mesh, glm::vec3 p, glm::vec3 q, glm::vec3 r) {
  for (const glm::vec3& c : {p, q, r}) {
    mesh.indices.push_back(static_cast<std::uint32_t>(mesh.positions.size()));
    mesh.positions.push_back(c);
  }
}

TEST_F(CollisionTest, InterpenetratingBoxesGiveTheCpuPairs) {
  SoupMesh mesh;
  deform::testing::add_box(mesh, glm::vec3(0.0f), glm::vec3(1.0f));
  deform::testing::add_box(mesh, glm::vec3(0.5f), glm::vec3(1.5f));
  const std::vector<TrianglePair> pairs = on_gpu(mesh, mesh.all_triangles());
  // Box A's +x face (triangles 2, 3) crosses box B's -y face (16, 17): part of the known set.
  EXPECT_TRUE(std::any_of(pairs.begin(), pairs.end(), [](const TrianglePair& p) {
    return (p.first == 2 || p.first == 3) && (p.second == 16 || p.second == 17);
  }));
  expect_same(mesh);
}

TEST_F(CollisionTest, NearMissesAndNeighboursGiveNoPairs) {
  SoupMesh mesh;
  deform::testing::add_box(mesh, glm::vec3(0.0f), glm::vec3(1.0f));
  deform::testing::add_box(mesh, glm::vec3(1.0001f, 0.0f, 0.0f), glm::vec3(2.0f, 1.0f, 1.0f));
  deform::testing::add_grid(mesh, {0, 1.00001f, 0}, {1, 0, 0}, {0, 0, 1}, 4);
  deform::testing::add_grid(mesh, {0, 3, 0}, {1, 0, 0}, {0, 1, 0}, 8);  // shared-edge neighbours
  EXPECT_TRUE(on_gpu(mesh, mesh.all_triangles()).empty());
  expect_same(mesh);
}

TEST_F(CollisionTest, TouchingAndCoplanarKnifeEdgesMatchTheCpu) {
  // Pairs whose answer hangs on exact zeros: a shared corner point, a shared edge segment, a
  // corner on the interior, coplanar overlap, coplanar containment, and coplanar apart.
  SoupMesh mesh;
  auto add = [&](glm::vec3 p, glm::vec3 q, glm::vec3 r) {
    for (const glm::vec3& c : {p, q, r}) {
      mesh.indices.push_back(static_cast<std::uint32_t>(mesh.positions.size()));
      mesh.positions.push_back(c);
    }
  };
  const glm::vec3 o(0, 0, 0), x(1, 0, 0), y(0, 1, 0);
  add(o, x, y);                                                    // 0: floor
  add(x, {2, 0, 1}, {2, 1, 1});                                    // 1: corner on corner
  add(x + glm::vec3(0, 0, 5), y + glm::vec3(0, 0, 5), {1, 1, 6});  // 2: far away
  add({0.2f, 0.2f, 0}, {0.2f, 0.5f, 1}, {0.5f, 0.2f, 1});          // 3: corner on interior
  add({0.1f, 0.1f, 0}, {0.3f, 0.1f, 0}, {0.1f, 0.3f, 0});          // 4: coplanar inside
  add({1.5f, 0, 0}, {2.5f, 0, 0}, {1.5f, 1, 0});                   // 5: coplanar apart
  add({1, 0, 0}, {1, 1, 0}, {0, 1, 0});                            // 6: coplanar edge touch
  const std::vector<TrianglePair> gpu = on_gpu(mesh, mesh.all_triangles());
  for (TrianglePair expected :
       {TrianglePair{0, 1}, TrianglePair{0, 3}, TrianglePair{0, 4}, TrianglePair{0, 6}}) {
    EXPECT_TRUE(std::binary_search(gpu.begin(), gpu.end(), expected))
        << expected.first << "-" << expected.second;
  }
  EXPECT_FALSE(std::binary_search(gpu.begin(), gpu.end(), TrianglePair{0, 5}));
  EXPECT_FALSE(std::binary_search(gpu.begin(), gpu.end(), TrianglePair{0, 2}));
  expect_same(mesh);
}

TEST_F(CollisionTest, RandomSoupsMatchTheCpuExactly) {
  for (unsigned seed : {11u, 12u, 13u}) {
    const SoupMesh soup = deform::testing::random_soup(800, 0.05f, seed);
    const std::vector<TrianglePair> gpu = on_gpu(soup, soup.all_triangles());
    EXPECT_GT(gpu.size(), 20u) << "seed " << seed;
    EXPECT_EQ(gpu, on_cpu(soup, soup.all_triangles())) << "seed " << seed;
  }
}

TEST_F(CollisionTest, MorePairsThanTheFirstBufferHolds) {
  // 3,000 tiny triangles crossing one big one... and each other: far beyond 4 x #T pairs.
  const SoupMesh soup = deform::testing::random_soup(1500, 0.5f, 5);
  const std::vector<TrianglePair> gpu = on_gpu(soup, soup.all_triangles());
  EXPECT_GT(gpu.size(), 4u * 1500u);
  EXPECT_EQ(gpu, on_cpu(soup, soup.all_triangles()));
}

TEST_F(CollisionTest, NearDegeneratePairsAreDecidedExactlyAsOnTheCpu) {
  // 1,000 pairs of 2 cm triangles at metre coordinates; the first 200 axis-aligned (their zeros
  // are exact), the others in a frame turned at random (so "on the plane" is only as exact as
  // float rounding makes it). Kinds, by k % 8: a corner on the other's face,
  // crossing edges meeting at a point, coplanar overlap, coplanar 1e-7 m apart, a shared edge's
  // positions (distinct indices) folded to random angles down to 0°, a corner 1e-7 m off the
  // other's face, clear crossings and clear misses.
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), angle(0.0f, 6.2831853f);
  SoupMesh mesh;
  const float s = 0.02f;
  for (int k = 0; k < 1000; ++k) {
    const glm::vec3 axis = glm::normalize(glm::vec3(unit(rng), unit(rng), unit(rng)) + 1e-3f);
    const glm::quat turn = k < 200 ? glm::quat(1, 0, 0, 0) : glm::angleAxis(angle(rng), axis);
    const glm::vec3 origin(0.5f + 0.1f * (k % 10), 0.5f + 0.1f * (k / 10 % 10), 0.5f + 0.1f * (k / 100));
    auto at = [&](float x, float y, float z) { return origin + turn * (s * glm::vec3(x, y, z)); };
    add_triangle(mesh, at(0, 0, 0), at(1, 0, 0), at(0, 1, 0));
    const float lift = 1e-7f / s, fold = angle(rng) / 12.0f;  // fold: 0 to 30°
    switch (k % 8) {
      case 0: add_triangle(mesh, at(0.2f, 0.2f, 0), at(0.3f, 0.1f, 1), at(0.1f, 0.3f, 1)); break;
      case 1: add_triangle(mesh, at(0.5f, 0.5f, -0.5f), at(0.5f, 0.5f, 0.5f), at(1, 1, 0)); break;
      case 2: add_triangle(mesh, at(0.3f, 0.3f, 0), at(1.2f, 0.3f, 0), at(0.3f, 1.2f, 0)); break;
      case 3: add_triangle(mesh, at(0.5f + lift, 0.5f + lift, 0), at(1, 1, 0), at(0.6f, 1, 0)); break;
      case 4:
        add_triangle(mesh, at(1, 0, 0), at(0, 1, 0),
                     at(std::cos(fold), std::cos(fold), std::sin(fold)));
        break;
      case 5: add_triangle(mesh, at(0.2f, 0.2f, lift), at(0.3f, 0.1f, 1), at(0.1f, 0.3f, 1)); break;
      case 6: add_triangle(mesh, at(0.2f, 0.2f, -0.5f), at(0.3f, 0.1f, 1), at(0.1f, 0.3f, 1)); break;
      default: add_triangle(mesh, at(0.2f, 0.2f, 0.1f), at(0.3f, 0.1f, 1), at(0.1f, 0.3f, 1)); break;
    }
  }
  const std::vector<std::uint32_t> ids = mesh.all_triangles();
  const std::vector<TrianglePair> gpu = on_gpu(mesh, ids);
  const CollisionStats stats = gpu_.last_stats();
  EXPECT_EQ(gpu, deform::testing::all_pairs_reference(mesh, ids));
  EXPECT_EQ(gpu, on_cpu(mesh, ids));
  std::printf("near-degenerate pairs: %zu found, %llu candidates, %llu undecided\n", gpu.size(),
              static_cast<unsigned long long>(stats.candidates),
              static_cast<unsigned long long>(stats.undecided));
  // The kinds that touch (0, 1, 2, 4) and cross (6) have overlapping boxes: 625 candidates at
  // least. The axis-aligned corner-on-face and coplanar pairs (25 of each) have exact zero
  // determinants, which no float test can certify: 50 undecided at least. The clear crossings
  // and misses are decided in float: at most the 750 other pairs are undecided.
  EXPECT_GE(stats.candidates, 625u);
  EXPECT_GE(stats.undecided, 50u);
  EXPECT_LE(stats.undecided, 750u);
  // The clear crossings are all found, the clear misses none, and the axis-aligned corner on a
  // face and coplanar overlaps (exact in float) are found: the known part of the answer.
  for (std::uint32_t k = 0; k < 1000; ++k) {
    const bool found = std::binary_search(gpu.begin(), gpu.end(), TrianglePair{2 * k, 2 * k + 1});
    if (k % 8 == 6) {
      EXPECT_TRUE(found) << "crossing " << k;
    } else if (k % 8 == 7) {
      EXPECT_FALSE(found) << "miss " << k;
    } else if (k < 200 && (k % 8 == 0 || k % 8 == 2)) {
      EXPECT_TRUE(found) << "touching " << k;
    }
  }
}

TEST_F(CollisionTest, ListsGoUpOnceAndShareASubmission) {
  SoupMesh mesh;
  deform::testing::add_subdivided_box(mesh, glm::vec3(0.0f), glm::vec3(1.0f), 6);
  const auto first_box = mesh.triangle_count();
  const std::size_t box_one_vertices = mesh.positions.size();
  deform::testing::add_subdivided_box(mesh, glm::vec3(0.6f, 0.5f, 0.4f), glm::vec3(1.5f), 6);
  const auto both = mesh.triangle_count();
  const std::size_t box_two_vertices = mesh.positions.size();
  deform::testing::add_subdivided_box(mesh, glm::vec3(3.0f), glm::vec3(4.0f), 20);  // alone
  std::vector<std::uint32_t> a, b, c;
  for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) (t < first_box ? a : t < both ? b : c).push_back(t);
  // Lists: box one with box two's first half, box two, the far box (no pairs).
  std::vector<std::uint32_t> ab = a;
  ab.insert(ab.end(), b.begin(), b.begin() + static_cast<std::ptrdiff_t>(b.size() / 2));
  const std::vector<std::uint32_t> all = mesh.all_triangles();
  const std::vector<std::span<const std::uint32_t>> lists = {ab, b, c, all};
  std::vector<std::vector<TrianglePair>> gpu(lists.size());
  gpu_.detect_all(mesh.positions, mesh.indices, lists, gpu);
  EXPECT_EQ(gpu_.last_stats().submissions, 1);
  EXPECT_EQ(gpu_.last_stats().lists, 4);
  for (std::size_t l = 0; l < lists.size(); ++l) {
    const std::vector<std::uint32_t> ids(lists[l].begin(), lists[l].end());
    EXPECT_EQ(gpu[l], on_cpu(mesh, ids)) << "list " << l;
  }
  EXPECT_EQ(gpu[0], deform::testing::all_pairs_reference(mesh, ab));
  EXPECT_FALSE(gpu[0].empty());
  EXPECT_TRUE(gpu[2].empty());

  // Unchanged positions: every list answered from that submission.
  std::vector<TrianglePair> pairs;
  gpu_.detect(mesh.positions, mesh.indices, ab, pairs);
  EXPECT_EQ(gpu_.last_stats().submissions, 0);
  EXPECT_EQ(pairs, gpu[0]);
  // The far box moves: only its list is stale, it goes up alone.
  for (std::size_t v = box_two_vertices; v < mesh.positions.size(); ++v) mesh.positions[v].y += 0.5f;
  gpu_.detect(mesh.positions, mesh.indices, c, pairs);
  EXPECT_EQ(gpu_.last_stats().lists, 1);
  EXPECT_TRUE(pairs.empty());
  // Box two moves into box one: asking for box two's list recomputes the other stale list that
  // is small (ab; the whole-mesh list is over a quarter of the mesh and waits to be asked).
  for (std::size_t v = box_one_vertices; v < box_two_vertices; ++v) mesh.positions[v].x -= 0.1f;
  gpu_.detect(mesh.positions, mesh.indices, b, pairs);
  EXPECT_EQ(gpu_.last_stats().submissions, 1);
  EXPECT_EQ(gpu_.last_stats().lists, 2);
  gpu_.detect(mesh.positions, mesh.indices, ab, pairs);
  EXPECT_EQ(gpu_.last_stats().submissions, 0);
  EXPECT_EQ(pairs, on_cpu(mesh, ab));
  gpu_.detect(mesh.positions, mesh.indices, all, pairs);
  EXPECT_EQ(gpu_.last_stats().lists, 1);
  EXPECT_EQ(pairs, on_cpu(mesh, all));

  // The same ids over other indices (the triangles renumbered): a different list, not a stale
  // answer.
  SoupMesh shuffled = mesh;
  for (std::size_t t = 0; t + 1 < shuffled.triangle_count(); t += 2)
    for (int k = 0; k < 3; ++k) std::swap(shuffled.indices[3 * t + k], shuffled.indices[3 * t + 3 + k]);
  gpu_.detect(shuffled.positions, shuffled.indices, ab, pairs);
  EXPECT_EQ(gpu_.last_stats().submissions, 1);
  EXPECT_EQ(pairs, on_cpu(shuffled, ab));
}

TEST_F(CollisionTest, NonFinitePositionsGiveTheCpuPairs) {
  SoupMesh mesh;
  deform::testing::add_box(mesh, glm::vec3(0.0f), glm::vec3(1.0f));
  deform::testing::add_box(mesh, glm::vec3(0.5f), glm::vec3(1.5f));
  mesh.positions[9].x = NAN;
  mesh.positions[3].z = INFINITY;
  EXPECT_EQ(on_gpu(mesh, mesh.all_triangles()), on_cpu(mesh, mesh.all_triangles()));
  EXPECT_EQ(gpu_.last_stats().cpu_lists, 1);
}

TEST_F(CollisionTest, BentMaleRegionsMatchTheCpuBeforeAndAfterFolding) {
  const auto file = std::filesystem::path(SWEEPD_SHARED_DATA) / "models/makehuman_male_cmu.glb";
  if (!std::filesystem::exists(file)) GTEST_SKIP() << "shared data absent: " << file;
  BentModel bent(io::load_gltf(file));
  const deform::CollisionRegions& regions = bent.regions;
  deform::test::Posing& deformer = bent.deformer;
  deform::Pose& pose = bent.pose;
  std::vector<glm::vec3>& positions = bent.positions;
  // Every region and the whole body, one submission, then each list answered from it.
  EXPECT_GT(expect_regions_and_body_match(positions, regions), 0u);

  deform::SkinFolder folder;
  std::size_t total = 0;
  std::vector<TrianglePair> cpu, gpu;
  for (const deform::CollisionRegion& region : regions.regions) {
    for (int round = 0; round < 2; ++round) {  // before and after folding
      SCOPED_TRACE(std::string(to_string(region.site)) + (round ? " folded" : ""));
      cpu_.detect(positions, regions.welded_indices, region.triangles, cpu);
      gpu_.detect(positions, regions.welded_indices, region.triangles, gpu);
      EXPECT_EQ(gpu, cpu);
      total += cpu.size();
      folder.fold(region, regions.welded_indices, cpu, 5e-4f, positions);
    }
  }
  EXPECT_GT(total, 0u) << "the bent elbow and knee must give pairs to compare";

  // The whole deformation job with folding, protrusion and volume, its pairs found on the GPU
  // (DeformJobOptions::detect), moves every vertex exactly as with the CPU reference.
  std::vector<glm::vec3> with_gpu(positions.size());
  deformer.features = {.folding = true, .protrusion = true, .volume = true, .bulge = false};
  deformer.deform(pose, deform::DeformMethod::kSweep, positions);
  const deform::FeatureReport on_cpu = deformer.report.features;
  deformer.options.detect = [&](auto p, auto i, auto t, std::vector<TrianglePair>& out) {
    gpu_.detect(p, i, t, out);
  };
  deformer.deform(pose, deform::DeformMethod::kSweep, with_gpu);
  const deform::FeatureReport on_gpu = deformer.report.features;
  EXPECT_GT(on_cpu.pairs_before, 0);
  EXPECT_EQ(on_gpu.pairs_before, on_cpu.pairs_before);
  EXPECT_EQ(on_gpu.pairs_after, on_cpu.pairs_after);
  EXPECT_EQ(on_gpu.folded, on_cpu.folded);
  EXPECT_EQ(with_gpu, positions);
  // After the detect -> fold/relax rounds both detectors still find the same pairs.
  for (const deform::CollisionRegion& region : regions.regions) {
    SCOPED_TRACE(std::string(to_string(region.site)) + " after the feature pass");
    cpu_.detect(positions, regions.welded_indices, region.triangles, cpu);
    gpu_.detect(positions, regions.welded_indices, region.triangles, gpu);
    EXPECT_EQ(gpu, cpu);
  }
}

TEST_F(CollisionTest, BentMannequinRegionsAndWholeBodyMatchTheCpu) {
  // The procedural mannequin (another mesh, another triangle size), elbow and knee flexed 150°,
  // as posed and rescaled to a tenth and mirrored (x -> -x): the cell size and the float
  // filter's bound follow the scale, the pairs stay the CPU's.
  BentModel bent(mannequin::make_mannequin({.target_vertices = 20000}));
  const deform::CollisionRegions& regions = bent.regions;
  std::vector<glm::vec3>& positions = bent.positions;
  EXPECT_GT(expect_regions_and_body_match(positions, regions), 0u)
      << "the bent mannequin must give pairs to compare";
  for (glm::vec3& p : positions) p = glm::vec3(-0.1f, 0.1f, 0.1f) * p;
  EXPECT_GT(expect_regions_and_body_match(positions, regions), 0u);
}

TEST_F(CollisionTest, WholeBodyContactMatchesTheCpuOnTheMannequin) {
  BentModel bent(mannequin::make_mannequin({.target_vertices = 6000}));
  deform::test::Posing& deformer = bent.deformer;
  deform::Pose& pose = bent.pose;
  std::vector<glm::vec3>& positions = bent.positions;
  std::vector<glm::vec3> with_gpu(positions.size());
  const deform::CollisionModel& collision = deformer.runtime.collision();
  std::vector<TrianglePair> cpu, gpu;
  deform::WholeBodyDetector whole_body;
  whole_body.detect(positions, collision.regions.welded_indices, collision.contact.skin_triangles,
                    cpu, 2);
  gpu_.detect(positions, collision.regions.welded_indices, collision.contact.skin_triangles, gpu);
  EXPECT_GT(cpu.size(), 0u) << "the bent elbow and knee must give pairs to compare";
  EXPECT_EQ(gpu, cpu);
  // The contact feature with the GPU's pairs (the same hook as folding's) moves every vertex
  // exactly as with the CPU's. Flexed 140°, not 150°: at 150° every contact group on this mesh
  // would tear the skin or add pairs and is undone (measured 207 -> 207 pairs), so the two
  // backends would be compared on the plain sweep; at 140° contact moves it (159 -> 106).
  pose = deform::test::left_elbow_and_knee_flexed(bent.bound.model, 140.0f);
  deformer.features = {.contact = true};
  deformer.deform(pose, deform::DeformMethod::kSweep, positions);
  const deform::FeatureReport on_cpu = deformer.report.features;
  deformer.options.detect = [&](auto p, auto i, auto t, std::vector<TrianglePair>& out) {
    gpu_.detect(p, i, t, out);
  };
  deformer.deform(pose, deform::DeformMethod::kSweep, with_gpu);
  const deform::FeatureReport on_gpu = deformer.report.features;
  EXPECT_GT(on_cpu.contact_pairs_before, on_cpu.contact_pairs_after);
  EXPECT_EQ(on_gpu.contact_pairs_before, on_cpu.contact_pairs_before);
  EXPECT_EQ(on_gpu.contact_pairs_after, on_cpu.contact_pairs_after);
  EXPECT_EQ(with_gpu, positions);
}

}  // namespace
}  // namespace sweepd::gpu
