// DeformJob: one deformation — a pose in, a deformed mesh out — as ozz-animation's jobs are: a
// plain struct of inputs and caller-owned output buffers, validate() once, run(context).
//
// Inputs:  runtime    the model's ModelRuntime (model_runtime.h), shared read-only
//          pose       J local rotations and the root translation (normalised in place)
//          method     sweep (the paper) or the LBS/DQS baselines
//          features   AnatomicalFeatures (sweep only): folding, protrusion, volume, bulge,
//                     contact
//          options    edits on/off, volume/bulge options, where I_C comes from, the pair
//                     finder for folding (empty: the CPU reference; gpu::CollisionDetector
//                     plugs in here), threads
// Outputs: positions  #V; normals #V, or empty to skip
//          DeformReport: what folding and protrusion did, the I_C the volume target used,
//          the volume corrections, and how many times the mesh was deformed.
//
// validate(): once per pose — checks the pose against the skeleton (non-unit quaternions
//   within options.rotation_length_tolerance are normalised in place) and that method,
//   features and options go together; returns a JobProblem naming what is wrong, which input
//   (joint count, pose, selection), or none.
// run(context): validate(), then run_validated(); a problem is thrown as std::invalid_argument
//   "invalid pose: <why>" or the selection's reason.
// run_validated(context): for a caller that already validated the job (the daemon validates a
//   pose when it arrives, on its I/O thread, and deforms it later on a worker). Checks only the
//   sizes that guard memory — joint count, output buffers of #V — in O(1), and throws
//   std::invalid_argument naming them.
// run(), in one direction: forward kinematics → posed keys (edits, bulge; §4.1–4.3) → volume
//   (§4.4: towards I0 − I_C) → vertices and blending (§3.3–3.5) → folding, protrusion (§4.3),
//   contact (whole body) →
//   normals (WeldedNormals, after the features, so they see the moved skin).
// One I_C (§4.4): the volume folding, protrusion and contact add, per sweep, as CollisionFeatures
//   measures it (sweep_volume_change). In a stream (kPreviousFrame) it is the previous frame's,
//   kept in the context; a frame that stands alone (kFixedPoint, or a stream's first frame)
//   runs a short fixed-point loop instead — deform, measure, re-target — for at most
//   fixed_point_rounds deformations, stopping once the measured I_C moves less than the volume
//   tolerance (× I0) from the one targeted. Without folding and protrusion I_C is 0 and the
//   mesh is deformed once. Nothing is allocated per frame once the context is warm; threads
//   > 1 splits the vertex loops with bit-identical results.
#pragma once

#include <chrono>
#include <glm/glm.hpp>
#include <limits>
#include <span>
#include <string>

#include "deform/features/collision_features.h"
#include "deform/features/muscle_bulge.h"
#include "deform/job/anatomical_features.h"
#include "deform/job/deform_context.h"
#include "deform/job/deform_method.h"
#include "deform/job/job_problem.h"
#include "deform/job/model_runtime.h"
#include "deform/model/pose.h"
#include "deform/volume/volume_preservation.h"

namespace sweepd::deform {

enum class VolumeChangeSource {
  kFixedPoint,     // every frame stands alone (a render farm, one CLI frame, a server request)
  kPreviousFrame,  // frames of one stream, in order, through one context
};

struct DeformJobOptions {
  bool edits = true;  // §4.2: the model's key-ellipse edits (ModelRuntime::edits)
  VolumePreservationOptions volume{};
  MuscleBulgeOptions bulge{};
  CollisionFeatureOptions collision{};  // rounds and gaps; `features` selects what runs
  VolumeChangeSource volume_change = VolumeChangeSource::kFixedPoint;
  int fixed_point_rounds = 3;  // deformations per frame at most, when volume meets folding
  // A rotation whose length differs from 1 by more is refused, not normalised (default: any
  // non-zero length is a direction; the daemon refuses what its wire contract does not allow).
  double rotation_length_tolerance = std::numeric_limits<double>::infinity();
  // Volume added elsewhere, per sweep (bound.sweeps.size() values, or empty): added to I_C.
  std::span<const double> added_volume{};
  DetectPairs detect{};  // folding's and contact's pair finder; empty: the CPU reference
  int threads = 1;
};

struct DeformReport {
  FeatureReport features{};  // the last round's folding and protrusion (times: all rounds')
  std::span<const double> volume_change{};          // per sweep: the I_C targeted (m³); sweep only
  std::span<const VolumeCorrection> corrections{};  // per sweep; empty without volume
  int rounds = 0;                                   // deformations of the mesh this frame
  std::chrono::nanoseconds features_time{0};        // spent in folding and protrusion
};

struct DeformJob {
  const ModelRuntime& runtime;
  Pose& pose;
  DeformMethod method = DeformMethod::kSweep;
  AnatomicalFeatures features{};
  DeformJobOptions options{};
  std::span<glm::vec3> positions{};
  std::span<glm::vec3> normals{};

  JobProblem validate();
  DeformReport run(DeformContext& context);
  DeformReport run_validated(DeformContext& context);

 private:
  // The sweep method with its features, into positions (normals after).
  void run_sweep(DeformContext& context, DeformReport& report);
};

}  // namespace sweepd::deform
