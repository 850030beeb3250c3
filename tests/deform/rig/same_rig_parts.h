// Test helper: expects two rig maps of skeletons with the same joint ids to pick the same joint
// for every role and chain (how each part was found, the convention and warnings aside).
#pragma once

#include <gtest/gtest.h>

#include "deform/rig/rig_map.h"

namespace sweepd::deform::test {

inline void expect_same_rig_parts(const RigMap& a, const RigMap& b) {
  EXPECT_EQ(a.torso.chain, b.torso.chain);
  EXPECT_EQ(a.neck.chain, b.neck.chain);
  EXPECT_EQ(a.neck.head, b.neck.head);
  EXPECT_EQ(a.left_arm.chain(), b.left_arm.chain());
  EXPECT_EQ(a.left_arm.clavicle, b.left_arm.clavicle);
  EXPECT_EQ(a.right_arm.chain(), b.right_arm.chain());
  EXPECT_EQ(a.right_arm.clavicle, b.right_arm.clavicle);
  EXPECT_EQ(a.left_leg.chain(), b.left_leg.chain());
  EXPECT_EQ(a.left_leg.hip, b.left_leg.hip);
  EXPECT_EQ(a.left_leg.toe, b.left_leg.toe);
  EXPECT_EQ(a.right_leg.chain(), b.right_leg.chain());
  EXPECT_EQ(a.right_leg.hip, b.right_leg.hip);
  EXPECT_EQ(a.right_leg.toe, b.right_leg.toe);
}

}  // namespace sweepd::deform::test
