// BoundModel: a Model bound to its control sweep surfaces (paper §3) — what bind() produces,
// what .sweepbind files store, and what the poser deforms.
//
// Per sweep (torso, neck, arms, legs): the joint chain it follows, its key ellipses in the rest
// pose with the joint or link each one is attached to, and its rest volume.
// Per vertex: up to three sweep coordinates (t, θ, displacement, c) with blend weights, plus the
// share that follows the model's own skin weights (hands, feet, head, and the hand-over zones).
// The weights of a vertex sum to 1.
// Edits: the user's key-ellipse corrections as functions of joint angles (paper §4.2).
#pragma once

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "deform/edits/angle_driven_key_edits.h"
#include "deform/model/model.h"
#include "deform/rig/rig_map.h"
#include "deform/sweep/interpolating_splines.h"
#include "deform/sweep/key_ellipse.h"
#include "deform/sweep/orientation_curve.h"

namespace sweepd::deform {

// Where a key ellipse sits on its chain: at chain joint `joint` (fraction 0: a joint key, whose
// centre moves with the joint and whose orientation follows both links), or a fraction of the
// way along the link from `joint` to `next_joint` (a link key, moving rigidly with that link).
struct KeyAnchor {
  int joint = -1;
  int next_joint = -1;  // -1 for the last joint key of the chain
  float fraction = 0.0f;
  bool is_joint_key() const { return fraction == 0.0f; }
  // A key past the chain's last joint, on the end its bone carries (a forearm bone that carries
  // the hand, a neck bone that carries the head: carried_end.h): it rides that joint's bone
  // rigidly, at `fraction` of the way from the joint to the end (1: the end's own key).
  bool is_on_carried_end() const { return next_joint < 0 && fraction > 0.0f; }
};

// What a sweep was bound with, where it may differ from the model's BindOptions: bind() copies
// the options' keys per link and orientation curve; the binding's self-check
// (selfcheck/binding_self_check.h) may choose others for a sweep that lost to skinning on the
// range of motion, and records the (pose, region) pairs worse than skinning before and after.
enum class SweepChoiceOrigin : std::uint8_t {
  kBindOptions = 0,  // the BindOptions' values
  kSelfCheck = 1,    // chosen by the self-check: fewer (pose, region) pairs worse than skinning
};
struct SweepChoice {
  OrientationCurveKind orientation_curve = OrientationCurveKind::kLinear;
  std::int32_t keys_per_link = 2;  // the link keys between two joint keys it was fitted with
  SweepChoiceOrigin origin = SweepChoiceOrigin::kBindOptions;
  std::uint32_t worse_before = 0, worse_after = 0;  // kSelfCheck: its measure, before and after
};

struct BoundSweep {
  BodyPart part = BodyPart::kNone;  // kTorso, kNeck, kLeftArm, kRightArm, kLeftLeg, kRightLeg
  std::vector<int> chain;           // joints the sweep follows, root first
  std::vector<KeyAnchor> anchors;   // one per key ellipse, in sweep order
  std::vector<KeyEllipse> rest_keys;
  std::vector<float> key_fit_errors;       // relative RMS fit error of each key (0 for fallbacks)
  std::vector<float> key_area_ratios;      // ellipse area / cross-section polygon area, per key
  std::vector<std::uint8_t> key_fallback;  // 1 where the cut was unusable and the key copied
  double rest_volume = 0.0;                // the swept volume of the rest keys (m³)
  SweepChoice choice;  // its orientation curve (what rest_sweep builds) and keys per link

  // The points the sweep runs through at rest: its chain's joints, then, where its last bone
  // carries an end (KeyAnchor::is_on_carried_end), the centre of the end's key.
  std::vector<glm::vec3> rest_path(std::span<const glm::mat4> world_rest) const;
  bool ends_on_carried_end() const {
    return !anchors.empty() && anchors.back().is_on_carried_end();
  }
};

// A vertex's place on one sweep: V = C(t) + R(t) ((a(t)+da) cos θ, (b(t)+db) sin θ, c).
// da, db are the paper's displacement d_V; c is the offset along N(t) that the paper drops and
// we keep, so that the rest pose reconstructs exactly.
struct SweepCoordinate {
  float t = 0.0f;
  float theta = 0.0f;
  float da = 0.0f;
  float db = 0.0f;
  float c = 0.0f;
};

// Up to three sweeps meet at a vertex: the torso and both legs in the crotch.
inline constexpr int kSweepsPerVertex = 3;

struct VertexBinding {
  std::array<std::int16_t, 4> sweep{-1, -1, -1, -1};  // into BoundModel::sweeps, -1 unused;
                                                      // the 4th keeps the record unpadded
  std::array<float, kSweepsPerVertex> weight{};
  std::array<SweepCoordinate, kSweepsPerVertex> coordinate{};
  float skin_weight = 0.0f;  // share that follows the model's own skinning (LBS)
};

enum class JointKeyCentre : std::int32_t {
  kAtJoint = 0,            // the paper: C(t) through the joint (ellipse: KeyEllipse::offset)
  kAtSectionCentroid = 1,  // at its section's centroid, carried rigidly by the joint
  kAuto = 2,  // the joint, unless it lies outside the inner half of its section's ellipse
};

struct BindOptions {
  int intermediate_keys_per_link = 1;  // link keys between two joint keys (paper Fig. 3: >= 1)
  // Spines are rigged near the back (the shared male's lie 6-9 cm behind the torso's centre),
  // where a joint-centred ellipse misfits its section by ~40 %; the centroid fits within ~5 %
  // and still moves with the joint. kAtJoint is the paper's rule; kAuto keeps it for limbs,
  // whose joints sit inside their sections, so a limb's keys stay on its bones.
  JointKeyCentre joint_key_centre = JointKeyCentre::kAuto;
  // The centre curve C(t): the paper's C2 cubic B-spline interpolant (kNotAKnot) reaches along
  // the whole limb, so bending an elbow moves the shoulder end by millimetres; kLocal (C1)
  // keeps every span two keys away from a bent joint rigid with its bone.
  SplineEnds centre_curve = SplineEnds::kLocal;
  int plane_samples_per_span = 16;  // sampled planes P(t_j) between two keys (§3.3)
  // Half-width of the shoulder/hip/neck-base transition, as a fraction of the limb's first link.
  float transition_half_width = 0.3f;
  // Half-width of the hand-over to the skinned hand/foot/head, as a fraction of the last link.
  float end_blend_half_width = 0.12f;
  // The orientation curve Q(t): the paper's piecewise-linear unit quaternions (kLinear), whose
  // turning rate jumps at every key, or the C2 cumulative B-spline through the end keys and near
  // the inner ones (kSmooth; deform/sweep/orientation_curve.h). Last: .sweepbind version 7 on.
  // bind() gives every sweep this curve and intermediate_keys_per_link (BoundSweep::choice);
  // the self-check may choose others per sweep, which the sweeps then follow.
  OrientationCurveKind orientation_curve = OrientationCurveKind::kLinear;
};

struct BoundModel {
  Model model;
  RigMap rig;
  BindOptions options;
  std::vector<BoundSweep> sweeps;
  std::vector<VertexBinding> vertices;  // one per model vertex
  // The influences each vertex's skinned share follows, one per vertex (empty: the model's own):
  // the model's weights, smoothed where an arm sweep meets the torso (skinned_share_influences.h).
  std::vector<std::array<std::uint16_t, kInfluences>> skinned_share_joints;
  std::vector<std::array<float, kInfluences>> skinned_share_weights;
  KeyEllipseEdits edits;  // key-ellipse corrections (empty: none)
};

}  // namespace sweepd::deform
