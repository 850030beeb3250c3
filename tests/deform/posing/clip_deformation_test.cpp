// Every frame of both shared CMU clips, retargeted onto each shared model (the MakeHuman male
// and Khronos' RiggedFigure) and the procedural mannequin, and deformed with sweeps and with LBS:
// finite everywhere, and each region's largest edge stretch (posed length over rest length)
// reported with its frame and edge. Regions: the hips (an end shares both leg sweeps: the crotch,
// the buttocks, the lower back), else the body part of the joint that weighs most on the edge's
// first vertex. The bound, 3x on every edge, holds in every region (asserted; measured
// worst on the male 2.87x on cmu_01_01 and 2.86x on cmu_01_03, both in the left arm; the torso
// 2.75x behind the left armpit with the arm overhead, 2.88x before the torso's key centres were
// laid along its centre line and 2.99x before its link keys spread the spine's bend); on
// the RiggedFigure 1.51x and 1.66x, below LBS's 1.67x and 1.76x). What brought it there:
// length-weighted share smoothing at the crotch (4.3x / 6.1x before), the
// clip's fingers, thumbs and toes left undriven (CMU noise: thumb webbing 10.7x, toe crease
// 4.1x), the neck handing over to the head along the surface (throat 3.4x), and smoothed
// skinned weights around the arm's root (armpit 3.5x).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "deform/binding/bind.h"
#include "deform/job/deform_job.h"
#include "deform/rig/rig_map.h"
#include "io/bvh/bvh_load.h"
#include "io/gltf/gltf_load.h"
#include "mannequin/mannequin.h"
#include "motion/retarget.h"
#include "tests/deform/mesh_edges.h"
#include "tests/deform/shared_male.h"

namespace sweepd::deform::clip_deformation_test {
namespace {

namespace fs = std::filesystem;

constexpr int kRegions = static_cast<int>(BodyPart::kRightFoot) + 2;
constexpr int kHips = kRegions - 1;

const char* region_name(int region) {
  return region == kHips ? "hips" : to_string(static_cast<BodyPart>(region));
}

struct Edge {
  std::uint32_t a, b;
  float rest_length;
  int region;
};

struct Worst {
  float stretch = 0.0f;
  int frame = -1;
  const Edge* edge = nullptr;
};

bool shares_both_legs(const BoundModel& bound, std::uint32_t v) {
  int legs = 0;
  for (int k = 0; k < kSweepsPerVertex; ++k) {
    const int s = bound.vertices[v].sweep[k];
    if (s < 0 || bound.vertices[v].weight[k] <= 0.0f) continue;
    const BodyPart part = bound.sweeps[s].part;
    legs += part == BodyPart::kLeftLeg || part == BodyPart::kRightLeg;
  }
  return legs == 2;
}

std::vector<Edge> edges_by_region(const BoundModel& bound) {
  const std::vector<BodyPart> joint_part = label_joints(bound.rig, bound.model.skeleton);
  std::vector<Edge> edges;
  for (const test::MeshEdge& e : test::distinct_edges(bound.model)) {
    const int region = shares_both_legs(bound, e.a) || shares_both_legs(bound, e.b)
                           ? kHips
                           : static_cast<int>(test::heaviest_part(bound.model, joint_part, e.a));
    edges.push_back({e.a, e.b, e.rest_length, region});
  }
  return edges;
}

// Every `frame_step`th frame of each clip (every frame by default).
void expect_every_frame_within_the_bound(const Model& model, const std::string& name,
                                         int frame_step = 1) {
  const fs::path data(SWEEPD_SHARED_DATA);
  const BoundModel bound = bind(model, detect_rig_map(model.skeleton));
  test::Posing deformer(bound);
  const std::vector<Edge> edges = edges_by_region(bound);

  std::vector<glm::vec3> positions(model.vertex_count());
  for (const std::string clip : {"motion/cmu_01_01.bvh", "motion/cmu_01_03.bvh"}) {
    const motion::Retargeter retargeter(io::load_bvh(data / clip), model);
    std::array<std::array<Worst, kRegions>, 2> worst{};  // [sweep, lbs][region]
    for (DeformMethod method : {DeformMethod::kSweep, DeformMethod::kLbs}) {
      std::array<Worst, kRegions>& by_region = worst[method == DeformMethod::kSweep ? 0 : 1];
      int non_finite_frames = 0;
      for (int frame = 0; frame < retargeter.frame_count(); frame += frame_step) {
        Pose pose = retargeter.pose_at_frame(frame);
        deformer.deform(pose, method, positions, {});
        bool finite = true;
        for (const glm::vec3& p : positions)
          finite &= std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
        non_finite_frames += !finite;
        for (const Edge& e : edges) {
          const float stretch = glm::length(positions[e.a] - positions[e.b]) / e.rest_length;
          if (stretch > by_region[e.region].stretch) by_region[e.region] = {stretch, frame, &e};
        }
      }
      EXPECT_EQ(non_finite_frames, 0) << clip << " " << to_string(method);
    }
    std::printf("%s on %s, %d frames, every %d, largest edge stretch per region, sweep | lbs:\n",
                clip.c_str(), name.c_str(), retargeter.frame_count(), frame_step);
    float sweep_overall = 0.0f, lbs_overall = 0.0f;
    for (int r = 0; r < kRegions; ++r) {
      const Worst& s = worst[0][r];
      const Worst& l = worst[1][r];
      if (!s.edge) continue;
      std::printf("  %-10s %5.2fx frame %4d edge %5u-%5u (rest %5.2f mm) | %5.2fx frame %4d\n",
                  region_name(r), s.stretch, s.frame, s.edge->a, s.edge->b,
                  1e3f * s.edge->rest_length, l.stretch, l.frame);
      sweep_overall = std::max(sweep_overall, s.stretch);
      lbs_overall = std::max(lbs_overall, l.stretch);
    }
    std::printf("  overall    %5.2fx | %5.2fx\n", sweep_overall, lbs_overall);
    // The bound on every edge, region by region so a failure names where.
    for (int r = 0; r < kRegions; ++r)
      EXPECT_LE(worst[0][r].stretch, 3.0f) << clip << " " << region_name(r);
    // Overall the sweeps tear the skin less than LBS does.
    EXPECT_LT(sweep_overall, lbs_overall) << clip;
  }
}

TEST(ClipDeformation, EveryCmuFrameOnTheMaleIsFiniteAndEachRegionsStretchIsReported) {
  const fs::path male = fs::path(SWEEPD_SHARED_DATA) / "models/makehuman_male_cmu.glb";
  if (!fs::exists(male)) GTEST_SKIP() << "shared data absent: " << male;
  expect_every_frame_within_the_bound(io::load_gltf(male), male.filename());
}

TEST(ClipDeformation, EveryCmuFrameOnTheRiggedFigureIsFiniteAndWithinTheBound) {
  const fs::path figure = fs::path(SWEEPD_SHARED_DATA) / "models/RiggedFigure/RiggedFigure.gltf";
  if (!fs::exists(figure)) GTEST_SKIP() << "shared data absent: " << figure;
  expect_every_frame_within_the_bound(io::load_gltf(figure), figure.filename());
}

// The product's default model at its default size and at 3k. Measured: 20k 2.43x (cmu_01_01,
// the neck) and 2.56x (cmu_01_03, the left arm), LBS 5.67x and 6.70x; 3k 2.18x and 2.25x. The back
// of the 20k mannequin's crotch stretched 3.63x at cmu_01_03's high knee (frame 3249) before the
// leg shares were smoothed over the skin around the crotch (deform/blending/sweep_blending.cpp).
TEST(ClipDeformation, EveryCmuFrameOnTheMannequinIsFiniteAndWithinTheBound) {
  if (!fs::exists(fs::path(SWEEPD_SHARED_DATA) / "motion/cmu_01_01.bvh"))
    GTEST_SKIP() << "shared data absent: " << SWEEPD_SHARED_DATA;
  for (int vertices : {20000, 3000})
    expect_every_frame_within_the_bound(mannequin::make_mannequin({.target_vertices = vertices}),
                                        std::to_string(vertices) + " mannequin");
}

// The largest size (the benchmarks' 72k), every 4th frame to keep the test's time near the
// others'. Before the share smoothing's passes grew with the mesh's fineness, an edge at the side
// of the chest, where the arm sweep's share fell 0.11 across 8 mm, reached 4.33x with the arms
// raised (cmu_01_03 frame 3700).
TEST(ClipDeformation, EveryFourthCmuFrameOnThe72kMannequinIsFiniteAndWithinTheBound) {
  if (!fs::exists(fs::path(SWEEPD_SHARED_DATA) / "motion/cmu_01_01.bvh"))
    GTEST_SKIP() << "shared data absent: " << SWEEPD_SHARED_DATA;
  expect_every_frame_within_the_bound(mannequin::make_mannequin({.target_vertices = 72000}),
                                      "72k mannequin", 4);
}

}  // namespace
}  // namespace sweepd::deform::clip_deformation_test
