// Every frame of both shared CMU clips, retargeted onto the shared male and deformed with
// sweeps (and LBS, for comparison): finite everywhere; the largest edge stretch is reported.
// The bound (no edge over 3× its rest length) is not met yet: the crotch, where the
// torso and both leg sweeps meet, reaches 4-6x in the deepest frames (LBS: the thumb webbing
// 10x); see the closing note of issue 4.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>

#include "deform/bind.h"
#include "deform/deformer.h"
#include "deform/rig_map.h"
#include "io/bvh_load.h"
#include "io/bvh_retarget.h"
#include "io/gltf_load.h"

namespace sweepd::deform {
namespace {

namespace fs = std::filesystem;

struct Edge {
  std::uint32_t a, b;
  float rest_length;
  bool on_sweeps;  // both ends mostly on sweeps (not the skinned hands, feet and head)
};

TEST(ClipDeformation, EveryCmuFrameOnTheMaleDeformsToFiniteVertices) {
  const fs::path data(SWEEPD_SHARED_DATA);
  const fs::path male = data / "models/makehuman_male_cmu.glb";
  if (!fs::exists(male)) GTEST_SKIP() << "shared data absent: " << male;
  const Model model = io::load_gltf(male);
  const BoundModel bound = bind(model, detect_rig_map(model.skeleton));
  Deformer deformer(bound);

  std::set<std::pair<std::uint32_t, std::uint32_t>> seen;
  std::vector<Edge> edges;
  for (std::size_t t = 0; t < model.indices.size(); t += 3)
    for (int k = 0; k < 3; ++k) {
      std::uint32_t a = model.indices[t + k], b = model.indices[t + (k + 1) % 3];
      if (a > b) std::swap(a, b);
      if (!seen.insert({a, b}).second) continue;
      const float length = glm::length(model.positions[a] - model.positions[b]);
      if (length <= 0.0f) continue;
      edges.push_back(
          {a, b, length,
           bound.vertices[a].skin_weight < 0.5f && bound.vertices[b].skin_weight < 0.5f});
    }

  std::vector<glm::vec3> positions(model.vertex_count());
  for (const char* clip : {"motion/cmu_01_01.bvh", "motion/cmu_01_03.bvh"}) {
    const io::Retargeter retargeter(io::load_bvh(data / clip), model);
    float worst_by_method[2] = {0.0f, 0.0f};
    for (DeformMethod method : {DeformMethod::kSweep, DeformMethod::kLbs}) {
      float worst_sweep_edges = 0.0f, worst_any = 0.0f;
      int worst_frame = -1, non_finite_frames = 0;
      for (int frame = 0; frame < retargeter.frame_count(); ++frame) {
        Pose pose = retargeter.pose_at_frame(frame);
        deformer.deform(pose, method, positions, {});
        bool finite = true;
        for (const glm::vec3& p : positions)
          finite &= std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
        non_finite_frames += !finite;
        for (const Edge& e : edges) {
          const float stretch = glm::length(positions[e.a] - positions[e.b]) / e.rest_length;
          worst_any = std::max(worst_any, stretch);
          if (e.on_sweeps && stretch > worst_sweep_edges) {
            worst_sweep_edges = stretch;
            worst_frame = frame;
          }
        }
      }
      std::printf(
          "%s, %s: %d frames, largest edge stretch %.2fx on sweep-bound edges (frame %d), "
          "%.2fx overall (hands and feet included)\n",
          clip, to_string(method), retargeter.frame_count(), worst_sweep_edges, worst_frame,
          worst_any);
      EXPECT_EQ(non_finite_frames, 0) << clip << " " << to_string(method);
      worst_by_method[method == DeformMethod::kSweep ? 0 : 1] = worst_sweep_edges;
    }
    // Where sweeps govern, they tear the skin less than LBS does (measured 4.2 vs 8.3, 6.1 vs 9.2).
    EXPECT_LT(worst_by_method[0], worst_by_method[1]) << clip;
  }
}

}  // namespace
}  // namespace sweepd::deform
