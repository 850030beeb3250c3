// DeformJob: one deformation — a pose in, a deformed mesh out — as ozz-animation's jobs are: a
// plain struct of inputs and caller-owned output buffers, validate() once, run(context).
//
// Inputs:  runtime    the model's ModelRuntime (model_runtime.h), shared read-only
//          pose       J local rotations and the root translation (normalised in place)
//          method     sweep (the paper) or the LBS/DQS baselines
//          features   AnatomicalFeatures (sweep only): folding, protrusion, volume, bulge
//          options    edits on/off, volume/bulge options, where I_C comes from, the pair
//                     finder for folding (empty: the CPU reference; gpu::CollisionDetector
//                     plugs in here), threads
// Outputs: positions  #V; normals #V, or empty to skip
//          DeformReport: what folding and protrusion did, the I_C the volume target used,
//          the volume corrections, and how many times the mesh was deformed.
//
// validate(): "" or what is wrong — "invalid pose: <joint, NaN/Inf, zero quaternion, joint
//   count>" (non-unit quaternions are normalised in place), "output buffers must hold N
//   vertices", features on LBS/DQS, added volumes of the wrong size. run() validates and throws
//   std::invalid_argument with that text.
// run(), in one direction: forward kinematics → posed keys (edits, bulge; §4.1–4.3) → volume
//   (§4.4: towards I0 − I_C) → vertices and blending (§3.3–3.5) → folding, protrusion (§4.3) →
//   normals (WeldedNormals, after the features, so they see the moved skin).
// One I_C (§4.4): the volume folding and protrusion add, per sweep, as CollisionFeatures
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
#include <span>
#include <string>

#include "deform/features/collision_features.h"
#include "deform/features/muscle_bulge.h"
#include "deform/job/anatomical_features.h"
#include "deform/job/deform_context.h"
#include "deform/job/deform_method.h"
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
  CollisionFeatureOptions collision{};  // rounds and gaps; `features` selects folding/protrusion
  VolumeChangeSource volume_change = VolumeChangeSource::kFixedPoint;
  int fixed_point_rounds = 3;  // deformations per frame at most, when volume meets folding
  // Volume added elsewhere, per sweep (bound.sweeps.size() values, or empty): added to I_C.
  std::span<const double> added_volume{};
  DetectPairs detect{};  // folding's pair finder; empty: the CPU reference
  int threads = 1;
};

struct DeformReport {
  FeatureReport features{};                         // the last round's folding and protrusion
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

  std::string validate();
  DeformReport run(DeformContext& context);

 private:
  // The sweep method with its features, into positions (normals after).
  void run_sweep(DeformContext& context, DeformReport& report);
};

}  // namespace sweepd::deform
