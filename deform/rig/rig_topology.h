// Rig topology: finds a RigMap from the hierarchy and rest-pose geometry alone, for skeletons
// whose joint names say nothing (e.g. "joint_12").
//
// Input: a skeleton whose world rest pose is a standing human in any orientation (Y or Z up)
// and roughly an A- or T-pose. Output: the map, convention "topological". Throws
// std::invalid_argument naming the step that failed.
//
// How: the pelvis is the first joint below the root with three or more child chains; the
// spine is its child chain with the most joints (it carries arms and head), the legs the two
// others reaching furthest. The chest is the first joint up the spine with three or more child
// chains; "up" points from pelvis to chest; the neck is the chest's child chain pointing most
// upward, the arms the two others reaching furthest. Along each limb the two consecutive
// segments with the largest summed length are upper arm + forearm (thigh + shin); the joint
// before them, if any, is the clavicle (hip link), the joint after them the hand (foot) and,
// for legs, the next one the toe. The head is the first neck joint that branches or ends.
// Left is up x forward, forward taken from the feet (ankle to toe) when toes are present,
// otherwise the glTF convention (+Z when Y is up, -Y when Z is up).
#pragma once

#include "deform/model/skeleton.h"
#include "deform/rig/rig_map.h"

namespace sweepd::deform {

RigMap detect_rig_map_by_topology(const Skeleton& skeleton);

}  // namespace sweepd::deform
