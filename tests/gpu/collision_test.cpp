// GPU collision detection (gpu::CollisionDetector on llvmpipe or a real GPU) against the CPU
// reference: synthetic configurations with known answers, touching and coplanar knife edges,
// random soups, and the shared male's collision regions, elbow and knee flexed 150°, before and
// after folding (one fold, and the whole detect -> fold/relax feature pass with either detector);
// and whole-body contact on the procedural mannequin: the GPU's pairs over the whole skin equal
// deform::WholeBodyDetector's, and the contact feature moves the same vertices with either.
#include "gpu/collision.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <glm/gtc/quaternion.hpp>

#include "deform/binding/bind.h"
#include "deform/features/collision_features.h"
#include "deform/features/collision_regions.h"
#include "deform/features/skin_folding.h"
#include "deform/features/whole_body_detector.h"
#include "deform/job/deform_job.h"
#include "deform/rig/rig_map.h"
#include "io/gltf_load.h"
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

  Context context_;
  CollisionDetector gpu_{context_};
  deform::SelfIntersectionDetector cpu_;
};

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

TEST_F(CollisionTest, BentMaleRegionsMatchTheCpuBeforeAndAfterFolding) {
  const auto file = std::filesystem::path(SWEEPD_SHARED_DATA) / "models/makehuman_male_cmu.glb";
  if (!std::filesystem::exists(file)) GTEST_SKIP() << "shared data absent: " << file;
  const deform::Model model = io::load_gltf(file);
  const deform::BoundModel bound = deform::bind(model, deform::detect_rig_map(model.skeleton));
  const deform::CollisionRegions regions = deform::find_collision_regions(bound);
  deform::test::Posing deformer(bound);
  deform::Pose pose = deform::test::left_elbow_and_knee_flexed(model, 150.0f);
  std::vector<glm::vec3> positions(model.vertex_count());
  deformer.deform(pose, deform::DeformMethod::kSweep, positions, {});

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

TEST_F(CollisionTest, WholeBodyContactMatchesTheCpuOnTheMannequin) {
  const deform::Model model = mannequin::make_mannequin({.target_vertices = 6000});
  const deform::BoundModel bound = deform::bind(model, deform::detect_rig_map(model.skeleton));
  deform::test::Posing deformer(bound);
  const deform::CollisionModel& collision = deformer.runtime.collision();
  deform::Pose pose = deform::test::left_elbow_and_knee_flexed(model, 150.0f);
  std::vector<glm::vec3> positions(model.vertex_count()), with_gpu(model.vertex_count());
  deformer.deform(pose, deform::DeformMethod::kSweep, positions);
  std::vector<TrianglePair> cpu, gpu;
  deform::WholeBodyDetector whole_body;
  whole_body.detect(positions, collision.regions.welded_indices, collision.contact.skin_triangles,
                    cpu, 2);
  gpu_.detect(positions, collision.regions.welded_indices, collision.contact.skin_triangles, gpu);
  EXPECT_GT(cpu.size(), 0u) << "the bent elbow and knee must give pairs to compare";
  EXPECT_EQ(gpu, cpu);
  // The contact feature with the GPU's pairs (the same hook as folding's) moves every vertex
  // exactly as with the CPU's.
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
