// VolumePreserver: keeps the swept volume of arms, legs and torso at their rest value while
// posing (paper §4.4).
//
// Per sweep, I0 is the volume of the rest sweep. After SweepPoser::set_pose has moved the keys,
// apply() repeats the paper's gradient update on the half-axis controls α, β
// (volume_correction_step) towards the target I0 − I_C (I_C: the net volume that folding and
// protrusion add outside the integral — CollisionFeatures::sweep_volume_change, which DeformJob
// passes here — plus any the caller adds; 0 by default) on the joint key(s) that turned most
// from rest against their parent (every joint key whose turn is at least half the largest one;
// the skeleton's root counts as unturned: its turn is the whole body's) and, after
// `joint_key_iterations` steps (none by default), on their neighbouring keys as well, until
// |I − target| / I0 < tolerance or max_iterations; at a key where the sweep bends, only the
// half-axis across the bend plane (bend_plane_degrees). Then it refreshes the poser's sample
// table.
// Inputs:  the posed SweepPoser, the joint rotation deltas of the pose (J), I_C per sweep
//          (sweep_count() values, or empty for zeros).
// Outputs: the poser's α, β (changed in place), and last_corrections(): one record per sweep.
// Nothing is allocated per frame. The volume is the signed one of swept_volume.h. Throws
// std::invalid_argument when added_volume has the wrong size.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <span>
#include <vector>

#include "deform/binding/bound_model.h"
#include "deform/posing/sweep_poser.h"

namespace sweepd::deform {

struct VolumePreservationOptions {
  // Which sweeps are corrected: the paper's arms, legs and torso; the neck is off by default.
  bool arms = true, legs = true, torso = true, neck = false;
  double tolerance = 1e-3;  // on |I − target| / I0
  int max_iterations = 20;  // update steps per sweep and frame
  // Steps on the most-turned joint keys alone before their neighbours join. 0: the neighbours
  // take part from the first step, each control moved by its share of the gradient. A bent
  // joint key's basis function covers the inside of the bend, where the section (offset from
  // the joint, KeyEllipse::offset) turns backwards about the joint, so its gradient is small
  // (the shared male's elbow at 150°: ∂I/∂β 0.0018 against 0.010-0.013 for its neighbours) and
  // steps on it alone grow it without bound (×8.6 at 150°, closed arm region +9.9 %); with the
  // neighbours from the start it grows ×1.1 and the region stays within +1.5 %.
  int joint_key_iterations = 0;
  // At a control key where the sweep bends by at least this much between its neighbouring
  // keys, only the half-axis across the bend plane (along the bend axis) is corrected: growing
  // the one in the bend plane moves the ellipse's inner side past the bend's centre, where the
  // sweep folds through itself — the integral counts that fold negatively, so the correction
  // would chase its own loss. A negative value corrects both everywhere (the paper).
  float bend_plane_degrees = 10.0f;
};

// Whether a sweep of this body part is corrected under these options.
bool preserves_volume(BodyPart part, const VolumePreservationOptions& options);

struct VolumeCorrection {
  bool corrected = false;    // false where the part is off
  double rest_volume = 0.0;  // I0 (m³)
  double target = 0.0;       // I0 − I_C
  double before = 0.0;       // I after posing, before the correction
  double after = 0.0;        // I after the correction
  int iterations = 0;        // update steps taken
  int most_turned_key = -1;  // the key the correction started on
};

// I0 of every sweep of the bound model (its rest sweep's volume), bound.sweeps.size() values.
std::vector<double> rest_sweep_volumes(const BoundModel& bound);

class VolumePreserver {
 public:
  // rest_volumes: rest_sweep_volumes(bound), computed once per model. The BoundModel and the
  // volumes must outlive the preserver.
  VolumePreserver(const BoundModel& bound, std::span<const double> rest_volumes);

  void apply(SweepPoser& poser, std::span<const glm::quat> joint_rotation,
             const VolumePreservationOptions& options, std::span<const double> added_volume = {});

  double rest_volume(int sweep) const { return rest_volume_[sweep]; }
  std::span<const VolumeCorrection> last_corrections() const { return corrections_; }

 private:
  // The controls for a sweep's first steps (most-turned joint keys) and later ones (with their
  // neighbours); returns the most-turned key.
  int choose_controls(int sweep, std::span<const glm::quat> joint_rotation);
  // Splits `keys` into α and β controls, leaving out the bend-plane half-axis of bent keys.
  void split_axes(const Sweep& sweep, std::span<const int> keys,
                  const VolumePreservationOptions& options, std::vector<int>& alpha,
                  std::vector<int>& beta) const;

  const BoundModel& bound_;
  std::span<const double> rest_volume_;
  std::vector<VolumeCorrection> corrections_;
  std::vector<float> turn_;                                   // scratch: per key of one sweep
  std::vector<int> first_controls_, controls_;                // scratch: keys
  std::vector<int> first_alpha_, first_beta_, alpha_, beta_;  // scratch: per half-axis
  std::vector<double> delta_alpha_, delta_beta_;
};

}  // namespace sweepd::deform
