// find_carried_end: where a last bone that carries an end of the body stops being limb or neck
// and becomes that end. Some rigs give the hand or the head no joint of its own: OpenPose's
// forearm bone carries the hand, its neck bone the head. The binding still sweeps the forearm
// and the neck up to that end (bind.cpp), and the end moves rigidly with the bone; the skeleton
// does not say where the end begins, so the mesh does: the narrowest cross-section along the
// bone's axis within the range where the wrist or the neck's top lies on a human body.
//
// The bone's axis runs from its joint to the centroid of the vertices it carries (skin weight
// on the joint and its descendants of one half or more); its extent is their furthest
// projection on it (elbow to fingertips, neck base to crown). Planes orthogonal to the axis cut
// the mesh at kSamples places, walking outward from where the end may begin; the end is the
// narrowest closed loop around the axis before the sections widen into the end (the palm, the
// jaw) or leave the limb's tube.
// Inputs:  model (its skin weights and skeleton), mesh (the model welded: weld_mesh), world_rest
//          (one per joint), joint (the bone: its joint, at the elbow or the neck base), kind.
// Output:  CarriedEnd: found with the end's point on the axis, or the reason none was found
//          (no vertices carried, no closed section in the range).
#pragma once

#include <glm/glm.hpp>
#include <span>
#include <string>

#include "deform/mesh/welded_mesh.h"
#include "deform/model/model.h"

namespace sweepd::deform {

enum class CarriedEndKind { kHand, kHead };

struct CarriedEnd {
  bool found = false;
  glm::vec3 point{0.0f};     // the end's section centre on the axis (world rest, m)
  glm::vec3 axis{0.0f};      // unit, from the joint towards the end
  float fraction = 0.0f;     // of the carried extent along the axis, where the end lies
  float section_area = 0.0f; // of the narrowest section (m²)
  std::string problem;       // why not found
};

CarriedEnd find_carried_end(const Model& model, const WeldedMesh& mesh,
                            std::span<const glm::mat4> world_rest, int joint, CarriedEndKind kind);

}  // namespace sweepd::deform
