// Key-ellipse edits (paper §4.2): a user's corrections of a key ellipse — position offset,
// orientation, scale of the half-axes — as functions of one joint's angle, so that a shape
// fixed at an extreme pose (e.g. the shoulder at 120° abduction) fades in smoothly as the joint
// gets there and is absent at rest.
//
// An edit names a sweep, one of its keys, the driving joint and samples (angle → correction).
// The angle is the joint's turn from rest (joint_turn_from_rest.h), in degrees. A sample at 0° with
// no correction is implied (zero at rest); between samples the correction follows a monotone cubic
// Hermite spline (Fritsch–Carlson tangents, zero slope at the first and last sample), so it never
// overshoots the edited values, and beyond the last sample it stays there. With one edited sample
// the change per 1° is at most 1.5 × (edited value) / (edited angle). Applied to a posed key:
// centre += R (offset), orientation = orientation · exp(rotation), a *= scale_a, b *= scale_b,
// where R is the posed key's frame and rotation a rotation vector in that frame (degrees × unit
// axis). The edits go with the BoundModel they were made for (BoundModel::edits; sweep and key
// indices refer to it) and are stored in its .sweepbind file.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <span>
#include <string>
#include <vector>

#include "deform/sweep/key_ellipse.h"

namespace sweepd::deform {

struct BoundModel;

struct KeyEllipseCorrection {
  glm::vec3 offset{0.0f};    // metres, in the key's frame (x: a axis, y: b axis, z: normal)
  glm::vec3 rotation{0.0f};  // rotation vector in the key's frame, degrees
  float scale_a = 1.0f, scale_b = 1.0f;
};

struct KeyEllipseEditSample {
  float angle_degrees = 0.0f;
  KeyEllipseCorrection correction;
};
static_assert(sizeof(KeyEllipseEditSample) == 36, "stored packed in .sweepbind files");

struct KeyEllipseEdit {
  int sweep = -1;                             // into BoundModel::sweeps
  int key = -1;                               // into that sweep's keys
  int joint = -1;                             // the joint whose turn drives the edit
  std::vector<KeyEllipseEditSample> samples;  // any order; sorted by validate
};

struct KeyEllipseEdits {
  std::vector<KeyEllipseEdit> edits;
};

// Sorts every edit's samples by angle. Returns "" when the edits fit the bound model, else what
// is wrong (edit index, and the sweep/key/joint out of range, a duplicate or negative angle, a
// non-positive scale, a non-finite value).
std::string validate(KeyEllipseEdits& edits, const BoundModel& bound);

// The correction of one (validated) edit at a joint angle.
KeyEllipseCorrection correction_at(const KeyEllipseEdit& edit, float angle_degrees);

// Applies a correction to a posed key.
void apply_correction(const KeyEllipseCorrection& correction, KeyEllipse& key);

// Applies every edit of `sweep` to its posed keys. joint_rotation: J world rotation deltas.
void apply_key_ellipse_edits(const KeyEllipseEdits& edits, const BoundModel& bound, int sweep,
                             std::span<const glm::quat> joint_rotation, std::span<KeyEllipse> keys);

}  // namespace sweepd::deform
