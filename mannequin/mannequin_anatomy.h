// MannequinAnatomy: the design of the procedural mannequin — its skeleton (CMU MotionBuilder
// joint names, as in the shared MakeHuman male and the CMU BVH clips), the body parts whose
// smooth union is its skin, and the skinning chains that give the skin its weights.
//
// Rest pose: Y up, facing +Z, feet near y = 0, about 1.75 m tall, A-pose with the arms 40
// degrees below horizontal and the palms towards the thighs. Every joint's rest rotation is
// the identity (world-axis-aligned frames, translation only). Joints are parents-first.
#pragma once

#include <vector>

#include "deform/model/skeleton.h"
#include "mannequin/body_shape.h"
#include "mannequin/skin_chain.h"

namespace sweepd::mannequin {

struct MannequinAnatomy {
  deform::Skeleton skeleton;    // 31 joints, root Hips
  std::vector<BodyPart> parts;  // BodyPart::skin_chain indexes `chains`
  std::vector<SkinChain> chains;
};

MannequinAnatomy make_mannequin_anatomy();

}  // namespace sweepd::mannequin
