#include "motion/retarget.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <stdexcept>

#include "deform/rig/rig_map.h"
#include "motion/clip_arms_through_floor.h"
#include "motion/clip_resting_knees.h"
#include "motion/clip_up_axis.h"
#include "motion/name_list.h"
#include "motion/shortest_arc.h"

namespace sweepd::motion {

namespace {

constexpr int kUnmatched = -1;
constexpr int kLeftOut = -2;  // the name map says: leave this BVH joint unmapped

std::optional<deform::RigMap> rig_map_or_warning(const deform::Skeleton& skeleton,
                                                 const std::string& side,
                                                 std::vector<std::string>& warnings) {
  try {
    return deform::detect_rig_map(skeleton);
  } catch (const std::invalid_argument& e) {
    warnings.push_back("no rig map for the " + side + " (" + e.what() +
                       "): joints matched by name and hierarchy only");
    return std::nullopt;
  }
}

// (model joint, BVH joint) for every role both maps fill. A one-joint torso is the whole torso:
// it turns as the clip's chest does (its legs have joints of their own).
std::vector<std::pair<int, int>> role_pairs(const deform::RigMap& model,
                                            const deform::RigMap& bvh) {
  std::vector<std::pair<int, int>> pairs;
  if (model.torso.chain.size() >= 2) pairs.emplace_back(model.torso.pelvis(), bvh.torso.pelvis());
  pairs.emplace_back(model.torso.chest(), bvh.torso.chest());
  pairs.emplace_back(model.neck.head, bvh.neck.head);
  // The joints between: a Mixamo spine (Hips, Spine, Spine1, Spine2) against CMU's (Hips,
  // LowerBack, Spine, Spine1) matches neither by name nor, past a branching pelvis, by
  // hierarchy, and its middle joints stayed at rest: the whole bend fell on the chest joint.
  // Each model joint pairs with the clip joint at the nearest place along the clip's chain.
  const auto inner = [&](const std::vector<int>& m, const std::vector<int>& b,
                         std::size_t skip_last) {
    if (m.size() < 1 + skip_last || b.size() < 1 + skip_last) return;
    const std::size_t model_inner = m.size() - 1 - skip_last, clip_inner = b.size() - 1 - skip_last;
    if (model_inner == 0 || clip_inner == 0) return;
    int previous = -1;
    for (std::size_t i = 0; i < model_inner; ++i) {
      const double along = static_cast<double>(i + 1) / static_cast<double>(model_inner + 1);
      // Rounded half down: one model neck joint for CMU's Neck and Neck1 is the lower, Neck
      // (the joint the hierarchy matched it to before).
      const int k = std::clamp(static_cast<int>(std::ceil(along * (clip_inner + 1) - 0.5)) - 1, 0,
                               static_cast<int>(clip_inner) - 1);
      if (k == previous) continue;  // one clip joint drives one model joint
      pairs.emplace_back(m[1 + i], b[1 + k]);
      previous = k;
    }
  };
  inner(model.torso.chain, bvh.torso.chain, 1);  // between the pelvis and the chest
  // The neck chain starts below the chest and ends at the head: the joints before the head.
  if (!model.neck.chain.empty() && !bvh.neck.chain.empty()) {
    std::vector<int> m = {-1}, b = {-1};
    m.insert(m.end(), model.neck.chain.begin(), model.neck.chain.end());
    b.insert(b.end(), bvh.neck.chain.begin(), bvh.neck.chain.end());
    inner(m, b, 1);
  }
  const auto arm = [&](const deform::ArmJoints& m, const deform::ArmJoints& b) {
    pairs.insert(
        pairs.end(),
        {{m.clavicle, b.clavicle}, {m.upper, b.upper}, {m.lower, b.lower}, {m.hand, b.hand}});
  };
  const auto leg = [&](const deform::LegJoints& m, const deform::LegJoints& b) {
    pairs.insert(
        pairs.end(),
        {{m.hip, b.hip}, {m.upper, b.upper}, {m.lower, b.lower}, {m.foot, b.foot}, {m.toe, b.toe}});
  };
  arm(model.left_arm, bvh.left_arm);
  arm(model.right_arm, bvh.right_arm);
  leg(model.left_leg, bvh.left_leg);
  leg(model.right_leg, bvh.right_leg);
  return pairs;
}

std::vector<glm::vec3> world_rest_positions(const deform::Skeleton& skeleton) {
  std::vector<glm::vec3> positions;
  for (const glm::mat4& m : skeleton.world_rest_matrices()) positions.emplace_back(m[3]);
  return positions;
}

bool is_strict_descendant(const deform::Skeleton& skeleton, int joint, int ancestor) {
  for (int j = skeleton.joints[joint].parent; j >= 0; j = skeleton.joints[j].parent)
    if (j == ancestor) return true;
  return false;
}

// The drop from the pelvis to the hip joints plus thigh and shin, mean of both legs: the
// pelvis's height above the ankles on straight legs; nullopt without a map or where a leg lacks
// its hip, knee or ankle (a legless rig).
std::optional<float> straight_leg_length(const std::optional<deform::RigMap>& map,
                                         const std::vector<glm::vec3>& world, int pelvis) {
  const auto whole = [](const deform::LegJoints& leg) {
    return leg.upper >= 0 && leg.lower >= 0 && leg.foot >= 0;
  };
  if (!map || !whole(map->left_leg) || !whole(map->right_leg)) return std::nullopt;
  float sum = 0.0f;
  for (const deform::LegJoints* leg : {&map->left_leg, &map->right_leg})
    sum += world[pelvis].y - world[leg->upper].y +
           glm::distance(world[leg->upper], world[leg->lower]) +
           glm::distance(world[leg->lower], world[leg->foot]);
  return sum / 2.0f;
}

// The ankles' height above a floor in the rest pose, mean of both legs (a map with whole legs).
float rest_ankle_height(const deform::RigMap& map, const std::vector<glm::vec3>& world,
                        float floor) {
  return (world[map.left_leg.foot].y + world[map.right_leg.foot].y) / 2.0f - floor;
}

// The clip's ankles' height as it stands (see the header): the 10th percentile over its frames
// of the lower ankle's height above y = 0.
float clip_stance_ankle_height(const Clip& motion, const deform::RigMap& map) {
  std::vector<glm::quat> rotations(motion.joints.size()), world;
  std::vector<glm::vec3> translations(motion.joints.size()), position;
  std::vector<float> lower_ankle;
  for (int frame = 0; frame < motion.frame_count; ++frame) {
    motion.local_pose(frame, rotations, translations);
    clip_forward_kinematics(motion, rotations, translations, world, position);
    lower_ankle.push_back(std::min(position[map.left_leg.foot].y, position[map.right_leg.foot].y));
  }
  const auto tenth = lower_ankle.begin() + lower_ankle.size() / 10;
  std::nth_element(lower_ankle.begin(), tenth, lower_ankle.end());
  return *tenth;
}

float lowest_joint_height(const deform::Skeleton& skeleton) {
  float lowest = std::numeric_limits<float>::infinity();
  for (const glm::vec3& p : world_rest_positions(skeleton)) lowest = std::min(lowest, p.y);
  return lowest;
}

float lowest_vertex_height(const deform::Model& model) {
  float lowest = std::numeric_limits<float>::infinity();
  for (const glm::vec3& p : model.positions) lowest = std::min(lowest, p.y);
  return model.positions.empty() ? lowest_joint_height(model.skeleton) : lowest;
}

// The clip's rest pose has identity rotations: End Sites sit at their joint plus the offset.
float lowest_clip_height(const Clip& motion, const std::vector<glm::vec3>& world) {
  float lowest = std::numeric_limits<float>::infinity();
  for (std::size_t b = 0; b < motion.joints.size(); ++b) {
    lowest = std::min(lowest, world[b].y);
    if (motion.joints[b].end_site)
      lowest = std::min(lowest, world[b].y + motion.joints[b].end_site->y);
  }
  return lowest;
}

}  // namespace

const char* to_string(JointMatchReason reason) {
  switch (reason) {
    case JointMatchReason::kNameMap:
      return "name map";
    case JointMatchReason::kName:
      return "name";
    case JointMatchReason::kRole:
      return "role";
    case JointMatchReason::kHierarchy:
      return "hierarchy";
  }
  return "?";
}

Retargeter::Retargeter(Clip motion, const deform::Model& model, const JointNameMap& name_map,
                       Feet feet)
    : Retargeter(std::make_shared<const Clip>(std::move(motion)), model, name_map, feet) {}

Retargeter::Retargeter(std::shared_ptr<const Clip> motion, const deform::Model& model,
                       const JointNameMap& name_map, Feet feet)
    : Retargeter(std::move(motion), model.skeleton, name_map, lowest_vertex_height(model)) {
  if (feet == Feet::kFree || !model_map_) return;
  std::vector<bool> foot_joint(skeleton_.joints.size(), false);
  const std::vector<deform::BodyPart> parts = deform::label_joints(*model_map_, skeleton_);
  for (std::size_t j = 0; j < parts.size(); ++j)
    foot_joint[j] =
        parts[j] == deform::BodyPart::kLeftFoot || parts[j] == deform::BodyPart::kRightFoot;
  const auto samples = std::make_shared<const BodySamples>(model, foot_joint);
  const std::vector<int> contact_part =
      BodyContacts::part_of_samples(*model_map_, skeleton_, *samples);
  std::vector<float> lowered;  // the body's least drop per frame, for resting knees
  // The frames where the clip pushes an arm through its floor beside its lying torso: that arm
  // holds nothing up, and rises off the model's floor instead (motion/body_floor.h).
  std::vector<int> clip_torso;
  std::array<int, 2> clip_arms{-1, -1};
  const std::vector<int> joint_part = BodyContacts::part_of_joints(*model_map_, skeleton_);
  const deform::ArmJoints* arms[2] = {&model_map_->left_arm, &model_map_->right_arm};
  for (int m = 0; m < skeleton_.size(); ++m)
    if (joint_part[m] == BodyContacts::kBack || joint_part[m] == BodyContacts::kHips)
      clip_torso.push_back(bvh_of_model_[m]);
  for (int side = 0; side < 2; ++side)
    if (arms[side]->upper >= 0) clip_arms[side] = bvh_of_model_[arms[side]->upper];
  // A clip whose ankles do not stand near its floor (lying most of the time) has no stance hip
  // height: the rest pose's, which the root scale took.
  const float clip_hip =
      clip_hip_height_ > 0.0f ? clip_hip_height_ : model_hip_height_ / root_scale_;
  const std::vector<std::uint8_t> arms_through =
      clip_arms_through_floor(*motion_, clip_torso, clip_arms, clip_floor_, clip_hip);
  const auto plant = [&] {
    planting_ = FootPlanting::build(
        model, *model_map_, model_hip_height_, motion_->frame_count, motion_->frame_time,
        [this](int frame) { return unplanted_pose_at_frame(frame); }, lowered);
  };
  const auto lift = [&] {
    body_floor_ = BodyFloor::build(model, samples, foot_joint, lowest_vertex_height(model),
                                   motion_->frame_count, motion_->frame_time,
                                   [this](int frame) { return feet_planted_pose_at_frame(frame); },
                                   contact_part, arms_through,
                                   {LimbJoints{arms[0]->upper, arms[0]->lower, arms[0]->hand},
                                    LimbJoints{arms[1]->upper, arms[1]->lower, arms[1]->hand}});
  };
  plant();
  lift();
  // A resting knee held up by the model's proportions: the body comes down, planted and lifted
  // again; a second pass takes what a planted leg's IK took up of the first.
  for (int pass = 0; pass < 2 && planting_; ++pass) {
    std::vector<float> more = lower_resting_knees(lowered);
    if (more.empty()) break;
    lowered = std::move(more);
    plant();
    lift();
  }
  // Parts resting on the floor (motion/body_contacts.h), found on the lifted poses. Where the
  // back or hips, a knee beside its planted foot, or two limbs rest, the root is held and the
  // feet are planted again on the
  // held root; the limbs' holds are planned on those poses (their steps across do not depend on
  // the lift), and the body floor lifts the body again with every hold in place, so that no
  // hold puts a part below the floor.
  BodyContacts contacts = BodyContacts::find(
      skeleton_, *model_map_, model_hip_height_, *body_floor_, motion_->frame_count,
      motion_->frame_time, [this](int frame) { return lifted_pose_at_frame(frame); },
      [this](int side, int frame) { return planting_ && planting_->planted(side, frame); },
      [this](int frame) { return unplanted_pose_at_frame(frame); });
  if (feet == Feet::kPlantedOnly) {
    measured_contacts_ = std::move(contacts);
  } else if (contacts.any()) {
    body_contacts_ = std::move(contacts);
    if (body_contacts_->holds_root()) {
      // Planting again on the held root turns the thighs, and with them the back's and
      // hips' contact points, so the hold is refined over a few passes, planting again each
      // time.
      for (int pass = 0; pass < 4; ++pass) {
        plant();
        body_contacts_->refine_root([this](int frame) { return feet_planted_pose_at_frame(frame); },
                                    [this](int frame) { return unplanted_pose_at_frame(frame); });
      }
      plant();
    }
    const auto raised = [this](int side, int frame) {
      return body_floor_->raises_arm(side, frame);
    };
    body_contacts_->plan_limbs(
        [this](int frame) { return feet_planted_pose_at_frame(frame); },
        [this](int side, int frame) { return planting_ && planting_->planted(side, frame); },
        raised);
    lift();
    // The arms the body floor raises are held on the raised poses (the raise moves them).
    body_contacts_->plan_raised_arms([this](int frame) { return lifted_pose_at_frame(frame); },
                                     raised);
  }
  const auto cm = [](float m) { return std::to_string(static_cast<int>(std::lround(m * 100.0f))); };
  const float rise = body_floor_->largest_lift(), arm_rise = body_floor_->largest_arm_rise();
  // Only what was done: a body lying on arms the clip pushes through its floor may not rise.
  std::vector<std::string> raised;
  if (rise > 0.01f)
    raised.push_back("the body is raised by up to " + cm(rise) + " cm where they would");
  if (arm_rise > 0.01f)
    raised.push_back(
        "arms the clip pushes through its floor beside its lying torso are raised off it by up "
        "to " +
        cm(arm_rise) + " cm");
  if (!raised.empty())
    warnings_.push_back(
        "parts of the body went below the floor (the model's proportions are not the clip's): " +
        raised[0] + (raised.size() > 1 ? ", and " + raised[1] : ""));
}

Retargeter::Retargeter(Clip motion, deform::Skeleton skeleton, const JointNameMap& name_map)
    : Retargeter(std::move(motion), skeleton, name_map, lowest_joint_height(skeleton)) {}

Retargeter::Retargeter(Clip motion, deform::Skeleton skeleton, const JointNameMap& name_map,
                       float model_floor)
    : Retargeter(std::make_shared<const Clip>(std::move(motion)), std::move(skeleton), name_map,
                 model_floor) {}

Retargeter::Retargeter(std::shared_ptr<const Clip> motion, deform::Skeleton skeleton,
                       const JointNameMap& name_map, float model_floor)
    : motion_(std::move(motion)), skeleton_(std::move(skeleton)) {
  if (motion_->joints.empty() || motion_->frame_count < 1)
    throw std::invalid_argument("the motion has no joints or no frames to retarget");
  if (skeleton_.joints.empty()) throw std::invalid_argument("the model has no joints");
  const deform::Skeleton bvh = clip_rest_skeleton(*motion_);
  model_map_ = rig_map_or_warning(skeleton_, "model", warnings_);
  const OptionalRigMap& model_map = model_map_;
  const OptionalRigMap bvh_map = rig_map_or_warning(bvh, "BVH clip", warnings_);
  match_joints(bvh, model_map, bvh_map, name_map);
  std::vector<glm::quat> clip_world_rest(motion_->joints.size());
  for (std::size_t b = 0; b < motion_->joints.size(); ++b) {
    const ClipJoint& joint = motion_->joints[b];
    const glm::quat rest = glm::normalize(joint.rest_rotation);
    clip_world_rest[b] = joint.parent < 0 ? rest : clip_world_rest[joint.parent] * rest;
    clip_world_rest_inverse_.push_back(glm::inverse(clip_world_rest[b]));
  }
  compute_facing(bvh, model_map, bvh_map);
  compute_alignments(bvh, model_map);
  compute_root_scale(bvh, model_map, bvh_map, model_floor);
}

void Retargeter::compute_facing(const deform::Skeleton& bvh, const OptionalRigMap& model_map,
                                const OptionalRigMap& bvh_map) {
  if (!model_map || !bvh_map) return;
  auto horizontal_forward = [](const deform::RigMap& map, const deform::Skeleton& skeleton) {
    glm::vec3 forward = deform::rest_body_axes(map, skeleton.world_rest_matrices()).forward;
    forward.y = 0.0f;
    return forward;
  };
  const glm::vec3 model = horizontal_forward(*model_map, skeleton_);
  const glm::vec3 clip = horizontal_forward(*bvh_map, bvh);
  // A body lying down at rest has no horizontal forward to speak of: left as it is.
  constexpr float kLeastHorizontal = 0.5f;
  if (!(glm::length(model) > kLeastHorizontal) || !(glm::length(clip) > kLeastHorizontal)) return;
  const float angle = std::atan2(glm::cross(model, clip).y, glm::dot(model, clip));
  if (std::abs(angle) <= glm::radians(kSameFacingDegrees)) return;
  facing_turn_ = glm::angleAxis(angle, glm::vec3(0.0f, 1.0f, 0.0f));
  const glm::vec3 m = glm::normalize(model);
  char text[160];
  std::snprintf(text, sizeof text,
                "the model faces (%.2f, 0, %.2f) at rest, %.0f° from the clip's facing: it is "
                "turned to face the clip's way",
                m.x, m.z, glm::degrees(angle));
  warnings_.push_back(text);
}

void Retargeter::match_joints(const deform::Skeleton& bvh, const OptionalRigMap& model_map,
                              const OptionalRigMap& bvh_map, const JointNameMap& name_map) {
  bvh_of_model_.assign(skeleton_.joints.size(), kUnmatched);
  model_of_bvh_.assign(bvh.joints.size(), kUnmatched);
  std::vector<JointMatchReason> reason(skeleton_.joints.size());
  const auto match = [&](int model_joint, int bvh_joint, JointMatchReason why) {
    if (model_joint < 0 || bvh_joint < 0 || bvh_of_model_[model_joint] != kUnmatched ||
        model_of_bvh_[bvh_joint] != kUnmatched)
      return false;
    bvh_of_model_[model_joint] = bvh_joint;
    model_of_bvh_[bvh_joint] = model_joint;
    reason[model_joint] = why;
    return true;
  };

  const auto bad_map = [&](const std::string& reason) {
    return std::invalid_argument((name_map.source.empty() ? "joint name map" : name_map.source) +
                                 ": " + reason);
  };
  for (const JointNamePair& pair : name_map.pairs) {
    const int b = bvh.find(pair.clip_joint);
    if (b < 0) throw bad_map("the BVH clip has no joint named '" + pair.clip_joint + "'");
    if (!pair.model_joint) {
      if (model_of_bvh_[b] == kUnmatched) model_of_bvh_[b] = kLeftOut;
      continue;
    }
    const int m = skeleton_.find(*pair.model_joint);
    if (m < 0)
      throw bad_map("'" + pair.clip_joint + "': the model has no joint named '" +
                    *pair.model_joint + "'");
    if (!match(m, b, JointMatchReason::kNameMap))
      throw bad_map("'" + pair.clip_joint + "' -> '" + *pair.model_joint +
                    "': one of the two joints is already mapped");
  }

  // Fingers and thumbs are not measured (see the header): left out unless the name map drives
  // them.
  std::vector<bool> is_finger(bvh.joints.size(), false);  // named in the fingers' warning
  if (bvh_map) {
    std::vector<std::string> left_out;
    for (int b = 0; b < bvh.size(); ++b)
      for (int hand : {bvh_map->left_arm.hand, bvh_map->right_arm.hand})
        if (model_of_bvh_[b] == kUnmatched && is_strict_descendant(bvh, b, hand)) {
          model_of_bvh_[b] = kLeftOut;
          is_finger[b] = true;
          left_out.push_back(bvh.joints[b].name);
        }
    if (!left_out.empty()) {
      std::string names;
      for (const std::string& name : left_out) names += (names.empty() ? "" : ", ") + name;
      warnings_.push_back("the clip's fingers and thumbs are not driven (" + names +
                          "): pair them in a name map to drive them");
    }
  }

  for (int m = 0; m < skeleton_.size(); ++m)
    match(m, bvh.find(skeleton_.joints[m].name), JointMatchReason::kName);

  if (model_map && bvh_map)
    for (const auto& [m, b] : role_pairs(*model_map, *bvh_map))
      match(m, b, JointMatchReason::kRole);

  for (bool changed = true; changed;) {
    changed = false;
    for (int m = 0; m < skeleton_.size(); ++m) {
      const int b = bvh_of_model_[m];
      if (b < 0) continue;
      std::vector<int> model_children, bvh_children;
      for (int c : skeleton_.children(m))
        if (bvh_of_model_[c] == kUnmatched) model_children.push_back(c);
      for (int c : bvh.children(b))
        if (model_of_bvh_[c] == kUnmatched) bvh_children.push_back(c);
      if (model_children.size() == 1 && bvh_children.size() == 1)
        changed |= match(model_children[0], bvh_children[0], JointMatchReason::kHierarchy);
    }
  }

  // Toes are not measured either (see the header): matched, to aim the foot, but not driven
  // unless the name map pairs them.
  driven_.assign(skeleton_.joints.size(), false);
  std::string undriven;
  for (int m = 0; m < skeleton_.size(); ++m) {
    const int b = bvh_of_model_[m];
    if (b < 0) continue;
    bool below_toe = false;
    if (bvh_map && reason[m] != JointMatchReason::kNameMap)
      for (int toe : {bvh_map->left_leg.toe, bvh_map->right_leg.toe})
        below_toe |= toe >= 0 && (b == toe || is_strict_descendant(bvh, b, toe));
    driven_[m] = !below_toe;
    if (below_toe) undriven += (undriven.empty() ? "" : ", ") + bvh.joints[b].name;
    matches_.push_back({b, m, reason[m], driven_[m]});
  }
  if (!undriven.empty())
    warnings_.push_back("the clip's toes are not driven (" + undriven +
                        "): pair them in a name map to drive them");
  warn_unmapped(bvh, is_finger);
}

void Retargeter::warn_unmapped(const deform::Skeleton& bvh, const std::vector<bool>& is_finger) {
  // Nothing unmapped in silence: a clip joint whose name matches nothing (a typo, a joint the
  // model lacks) would leave its limb still without a word. The fingers' warning above names
  // the clip's fingers already.
  std::vector<std::string> clip_names, model_names;
  for (int b = 0; b < bvh.size(); ++b)
    if (model_of_bvh_[b] < 0 && !is_finger[b]) clip_names.push_back(bvh.joints[b].name);
  for (int m = 0; m < skeleton_.size(); ++m)
    if (!driven_[m]) model_names.push_back(skeleton_.joints[m].name);
  if (!clip_names.empty())
    warnings_.push_back("clip joints that drive no model joint (" +
                        std::to_string(clip_names.size()) + "): " + name_list(clip_names) +
                        "; pair them in a joint name map to drive them");
  if (!model_names.empty())
    warnings_.push_back("model joints the clip leaves without motion, at their rest rotation (" +
                        std::to_string(model_names.size()) + "): " + name_list(model_names));
}

void Retargeter::compute_alignments(const deform::Skeleton& bvh, const OptionalRigMap& model_map) {
  // The neck chain (neck to head) keeps its rest angles: a neck that leans at rest is anatomy,
  // not a pose (see the header). So do girdle bones (clavicles, hip links) set otherwise than
  // the clip's, relative to the chest or pelvis they ride on.
  std::vector<bool> keeps_rest(skeleton_.joints.size(), false);
  std::vector<bool> is_girdle(skeleton_.joints.size(), false);
  if (model_map) {
    for (int j : model_map->neck.chain) keeps_rest[j] = true;
    for (const deform::ArmJoints* arm : {&model_map->left_arm, &model_map->right_arm})
      if (arm->clavicle >= 0) is_girdle[arm->clavicle] = true;
    for (const deform::LegJoints* leg : {&model_map->left_leg, &model_map->right_leg})
      if (leg->hip >= 0) is_girdle[leg->hip] = true;
  }
  std::vector<bool> keeps_parent_angle(skeleton_.joints.size(), false);
  const std::vector<glm::vec3> model_world = world_rest_positions(skeleton_);
  const std::vector<glm::vec3> bvh_world = world_rest_positions(bvh);
  world_rest_.resize(skeleton_.joints.size());
  alignment_.resize(skeleton_.joints.size());
  for (int m = 0; m < skeleton_.size(); ++m) {
    const int parent = skeleton_.joints[m].parent;
    const glm::quat rest = glm::normalize(skeleton_.joints[m].rest_rotation);
    world_rest_[m] = parent < 0 ? rest : world_rest_[parent] * rest;
    alignment_[m] = parent < 0 ? facing_turn_ : alignment_[parent];
    const int b = bvh_of_model_[m];
    if (keeps_rest[m]) alignment_[m] = facing_turn_;
    if (b < 0 || keeps_rest[m]) continue;
    // The nearest matched descendants whose BVH joints descend from b.
    std::vector<int> bone_ends, stack = skeleton_.children(m);
    while (!stack.empty()) {
      const int c = stack.back();
      stack.pop_back();
      if (bvh_of_model_[c] < 0) {
        const std::vector<int> below = skeleton_.children(c);
        stack.insert(stack.end(), below.begin(), below.end());
      } else if (is_strict_descendant(bvh, bvh_of_model_[c], b)) {
        bone_ends.push_back(c);
      }
    }
    if (bone_ends.size() != 1) continue;
    const glm::vec3 model_bone = model_world[bone_ends[0]] - model_world[m];
    const glm::vec3 bvh_bone = bvh_world[bvh_of_model_[bone_ends[0]]] - bvh_world[b];
    constexpr float kShortest = 1e-6f;
    if (glm::length(model_bone) < kShortest || glm::length(bvh_bone) < kShortest) continue;
    const glm::vec3 model_direction = facing_turn_ * glm::normalize(model_bone);
    const glm::vec3 bvh_direction = glm::normalize(bvh_bone);
    if (is_girdle[m] && glm::dot(model_direction, bvh_direction) < kSameGirdle) {
      keeps_parent_angle[m] = true;  // alignment_[m] stays the chest's or the pelvis's
      continue;
    }
    alignment_[m] = shortest_arc(model_direction, bvh_direction) * facing_turn_;
  }
  if (model_map) find_shoulder_rhythms(*model_map, model_world, keeps_parent_angle);
}

void Retargeter::find_shoulder_rhythms(const deform::RigMap& model_map,
                                       const std::vector<glm::vec3>& model_world,
                                       const std::vector<bool>& keeps_parent_angle) {
  for (const deform::ArmJoints* arm : {&model_map.left_arm, &model_map.right_arm}) {
    const int clavicle = arm->clavicle, upper = arm->upper, lower = arm->lower;
    if (clavicle < 0 || upper < 0 || lower < 0 || !keeps_parent_angle[clavicle] ||
        !driven_[clavicle] || !driven_[upper])
      continue;
    if (skeleton_.joints[upper].parent != clavicle) continue;
    if (clip_joint_moves(bvh_of_model_[clavicle])) continue;  // the clip's own clavicle
    const int chest = skeleton_.joints[clavicle].parent;
    if (chest < 0) continue;
    const glm::vec3 arm_bone = model_world[lower] - model_world[upper];
    const glm::vec3 clavicle_bone = model_world[upper] - model_world[clavicle];
    if (glm::length(arm_bone) < 1e-6f || glm::length(clavicle_bone) < 1e-6f) continue;
    ShoulderRhythm rhythm;
    rhythm.clavicle = clavicle;
    rhythm.upper = upper;
    rhythm.chest = chest;
    rhythm.arm_bone = glm::inverse(world_rest_[upper]) * glm::normalize(arm_bone);
    rhythm.clavicle_bone = glm::inverse(world_rest_[clavicle]) * glm::normalize(clavicle_bone);
    rhythm.chest_up = glm::inverse(world_rest_[chest]) * glm::vec3(0.0f, 1.0f, 0.0f);
    rhythm.rest_elevation =
        std::acos(std::clamp(glm::dot(glm::normalize(arm_bone), glm::vec3(0, -1, 0)), -1.0f, 1.0f));
    shoulder_rhythms_.push_back(rhythm);
  }
}

bool Retargeter::clip_joint_moves(int clip_joint) const {
  constexpr float kStill = 0.9998477f;  // |q0 · q| = cos(half their angle): still within 2°
  std::vector<glm::quat> rotations(motion_->joints.size());
  std::vector<glm::vec3> translations(motion_->joints.size());
  motion_->local_pose(0, rotations, translations);
  const glm::quat first = rotations[clip_joint];
  for (int frame = 1; frame < motion_->frame_count; ++frame) {
    motion_->local_pose(frame, rotations, translations);
    if (std::abs(glm::dot(first, rotations[clip_joint])) < kStill) return true;
  }
  return false;
}

void Retargeter::apply_shoulder_rhythms(deform::Pose& pose, std::vector<glm::quat>& world) const {
  for (const ShoulderRhythm& rhythm : shoulder_rhythms_) {
    const glm::vec3 up = world[rhythm.chest] * rhythm.chest_up;
    const glm::vec3 arm = world[rhythm.upper] * rhythm.arm_bone;
    const float elevation = std::acos(std::clamp(glm::dot(arm, -up), -1.0f, 1.0f));
    const float turn = std::clamp(kShoulderRhythm * (elevation - rhythm.rest_elevation),
                                  -kLargestClavicleTurn, kLargestClavicleTurn);
    const glm::vec3 clavicle = world[rhythm.clavicle] * rhythm.clavicle_bone;
    const glm::vec3 axis = glm::cross(clavicle, up);
    if (glm::length(axis) < 1e-6f) continue;
    world[rhythm.clavicle] =
        glm::normalize(glm::angleAxis(turn, glm::normalize(axis)) * world[rhythm.clavicle]);
    pose.local_rotations[rhythm.clavicle] =
        glm::normalize(glm::inverse(world[rhythm.chest]) * world[rhythm.clavicle]);
    // The upper arm keeps its world rotation: the arm points where the clip's points.
    pose.local_rotations[rhythm.upper] =
        glm::normalize(glm::inverse(world[rhythm.clavicle]) * world[rhythm.upper]);
  }
}

void Retargeter::compute_root_scale(const deform::Skeleton& bvh, const OptionalRigMap& model_map,
                                    const OptionalRigMap& bvh_map, float model_floor) {
  bvh_pelvis_ = bvh_map ? bvh_map->torso.pelvis() : 0;
  model_pelvis_ = model_map ? model_map->torso.pelvis() : 0;
  const std::vector<glm::vec3> model_world = world_rest_positions(skeleton_);
  const std::vector<glm::vec3> bvh_world = world_rest_positions(bvh);
  // Where the pelvis stands once the facing turn has turned the body about the root joint.
  const glm::vec3 root_rest = skeleton_.joints[0].rest_translation;
  model_pelvis_rest_ = root_rest + facing_turn_ * (model_world[model_pelvis_] - root_rest);
  const float bvh_floor = lowest_clip_height(*motion_, bvh_world);
  float bvh_height = bvh_world[bvh_pelvis_].y - bvh_floor;
  if (const std::optional<float> legs = straight_leg_length(bvh_map, bvh_world, bvh_pelvis_)) {
    const float rest_ankle = rest_ankle_height(*bvh_map, bvh_world, bvh_floor);
    const float stance_ankle = clip_stance_ankle_height(*motion_, *bvh_map);
    const bool stands = stance_ankle > 0.0f && stance_ankle < kHighestStanceAnkle * *legs;
    if (!stands)
      warnings_.push_back(
          "the clip's ankles do not stand near its floor (y = 0; the lower "
          "ankle's 10th percentile is " +
          std::to_string(stance_ankle) + "): its hip height is measured in its rest pose");
    bvh_height = *legs + (stands ? stance_ankle : rest_ankle);
    if (stands) clip_ankle_height_ = stance_ankle, clip_hip_height_ = bvh_height;
  }
  model_hip_height_ = model_world[model_pelvis_].y - model_floor;
  if (const std::optional<float> legs = straight_leg_length(model_map, model_world, model_pelvis_))
    model_hip_height_ = *legs + rest_ankle_height(*model_map, model_world, model_floor);
  if (bvh_height > 0.0f && model_hip_height_ > 0.0f) {
    root_scale_ = model_hip_height_ / bvh_height;
  } else {
    warnings_.push_back("no hip height on one side: root translation not scaled");
  }
}

std::vector<float> Retargeter::lower_resting_knees(const std::vector<float>& lowered) const {
  if (!model_map_ || !planting_ || !body_floor_ || !(clip_hip_height_ > 0.0f)) return {};
  const auto clip_knee = [&](int model_knee) {
    return model_knee >= 0 ? bvh_of_model_[model_knee] : -1;
  };
  const std::array<std::vector<std::uint8_t>, 2> resting = clip_resting_knees(
      *motion_, {clip_knee(model_map_->left_leg.lower), clip_knee(model_map_->right_leg.lower)},
      clip_floor_, clip_ankle_height_, clip_hip_height_);
  const int n = motion_->frame_count;
  std::vector<float> drop = lowered.empty() ? std::vector<float>(n, 0.0f) : lowered;
  // A knee rests within a part's contact height (body_contacts.h); it is brought a millimetre
  // under it, so that round-off does not leave it on the line.
  const float rests = BodyContacts::kPartContactHeight * model_hip_height_ - 0.001f;
  bool more = false;
  for (int f = 0; f < n; ++f) {
    if (body_floor_->lift(f) > 0.0f) continue;  // another part is down already
    float up = 0.0f;
    for (int side = 0; side < 2; ++side)
      if (!resting[side].empty() && resting[side][f] &&
          BodyContacts::kLeftKnee + side < body_floor_->group_count())
        up = std::max(up, std::min(body_floor_->lowest(BodyContacts::kLeftKnee + side, f).height,
                                   body_floor_->lowest(BodyContacts::kHips, f).height) -
                              rests);
    if (up <= 0.0f) continue;
    drop[f] = planting_->drop(f) + up;
    more = true;
  }
  return more ? drop : std::vector<float>{};
}

std::vector<std::string> Retargeter::unmapped_bvh_joints() const {
  std::vector<std::string> names;
  for (std::size_t b = 0; b < motion_->joints.size(); ++b)
    if (model_of_bvh_[b] < 0) names.push_back(motion_->joints[b].name);
  return names;
}

std::vector<std::string> Retargeter::unmapped_model_joints() const {
  std::vector<std::string> names;
  for (int m = 0; m < skeleton_.size(); ++m)
    if (bvh_of_model_[m] < 0) names.push_back(skeleton_.joints[m].name);
  return names;
}

deform::Pose Retargeter::retarget(std::span<const glm::quat> bvh_local,
                                  std::span<const glm::vec3> bvh_translation,
                                  bool keep_root_rest) const {
  std::vector<glm::quat> bvh_world;
  std::vector<glm::vec3> bvh_position;
  clip_forward_kinematics(*motion_, bvh_local, bvh_translation, bvh_world, bvh_position);
  deform::Pose pose;
  pose.local_rotations.resize(skeleton_.joints.size());
  std::vector<glm::quat> world(skeleton_.joints.size());
  for (int m = 0; m < skeleton_.size(); ++m) {
    const deform::Joint& joint = skeleton_.joints[m];
    if (!driven_[m]) {  // unmatched or undriven: its rest rotation relative to its parent
      world[m] = joint.parent < 0 ? facing_turn_ * joint.rest_rotation
                                  : world[joint.parent] * joint.rest_rotation;
      pose.local_rotations[m] = joint.parent < 0 ? world[m] : joint.rest_rotation;
      continue;
    }
    const int b = bvh_of_model_[m];
    // D_b = W_b(frame) * W_b(rest)^-1 (for BVH, whose rest rotations are the identity, exactly
    // W_b(frame)).
    world[m] =
        glm::normalize(bvh_world[b] * clip_world_rest_inverse_[b] * alignment_[m] * world_rest_[m]);
    pose.local_rotations[m] =
        glm::normalize(joint.parent < 0 ? world[m] : glm::inverse(world[joint.parent]) * world[m]);
  }
  apply_shoulder_rhythms(pose, world);
  const glm::vec3 root_rest = skeleton_.joints[0].rest_translation;
  pose.root_translation =
      keep_root_rest ? root_rest
                     : root_rest + root_scale_ * bvh_position[bvh_pelvis_] - model_pelvis_rest_;
  return pose;
}

deform::Pose Retargeter::unplanted_pose_at_frame(int frame) const {
  std::vector<glm::quat> rotations(motion_->joints.size());
  std::vector<glm::vec3> translations(motion_->joints.size());
  motion_->local_pose(frame, rotations, translations);
  deform::Pose pose = retarget(rotations, translations, false);
  if (body_contacts_) body_contacts_->hold_root(frame * double{motion_->frame_time}, pose);
  return pose;
}

deform::Pose Retargeter::pose_at_frame(int frame) const {
  if (frame < 0 || frame >= motion_->frame_count)
    throw std::out_of_range("frame " + std::to_string(frame) + " is outside the clip's " +
                            std::to_string(motion_->frame_count) + " frames");
  return lifted_pose_at_frame(frame);
}

deform::Pose Retargeter::feet_planted_pose_at_frame(int frame) const {
  const double seconds = frame * double{motion_->frame_time};
  deform::Pose pose = unplanted_pose_at_frame(frame);
  if (planting_) planting_->apply(seconds, pose);
  if (body_contacts_) body_contacts_->hold_limbs(seconds, pose);
  return pose;
}

deform::Pose Retargeter::lifted_pose_at_frame(int frame) const {
  deform::Pose pose = feet_planted_pose_at_frame(frame);
  lift_and_raise(frame * double{motion_->frame_time}, pose);
  return pose;
}

deform::Pose Retargeter::pose_at_time(double seconds) const {
  std::vector<glm::quat> rotations(motion_->joints.size());
  std::vector<glm::vec3> translations(motion_->joints.size());
  motion_->local_pose_at_time(seconds, rotations, translations);
  deform::Pose pose = retarget(rotations, translations, false);
  if (body_contacts_) body_contacts_->hold_root(seconds, pose);
  if (planting_) planting_->apply(seconds, pose);
  if (body_contacts_) body_contacts_->hold_limbs(seconds, pose);
  lift_and_raise(seconds, pose);
  return pose;
}

void Retargeter::lift_and_raise(double seconds, deform::Pose& pose) const {
  if (!body_floor_) return;
  body_floor_->apply(seconds, pose);
  if (!body_contacts_) return;
  // An arm the floor raised, held where it rests, is raised again where the hold dipped it.
  body_contacts_->hold_raised_arms(seconds, *body_floor_, pose);
}

deform::Pose Retargeter::pose_at_bvh_rest() const {
  const std::size_t count = motion_->joints.size();
  std::vector<glm::quat> rotations(count);
  std::vector<glm::vec3> translations(count);
  for (std::size_t b = 0; b < count; ++b) {
    rotations[b] = motion_->joints[b].rest_rotation;
    translations[b] = motion_->joints[b].offset;
  }
  return retarget(rotations, translations, true);
}

}  // namespace sweepd::motion
