#include "mannequin/mannequin_anatomy.h"

#include <cmath>
#include <numbers>
#include <string>

namespace sweepd::mannequin {

using deform::Joint;
using deform::Skeleton;

namespace {

constexpr float kArmDropDegrees = 40.0f;
const glm::vec3 kUp(0.0f, 1.0f, 0.0f);
const glm::vec3 kFront(0.0f, 0.0f, 1.0f);

enum Chain : int { kSpineChain, kLeftLeg, kRightLeg, kLeftArm, kRightArm, kLeftThumb, kRightThumb };

// Builds the skeleton from world positions (rest rotations stay identity).
class SkeletonBuilder {
 public:
  int add(const std::string& name, const std::string& parent, const glm::vec3& world) {
    Joint joint;
    joint.name = name;
    joint.parent = parent.empty() ? -1 : skeleton_.find(parent);
    joint.rest_translation = joint.parent < 0 ? world : world - world_[joint.parent];
    skeleton_.joints.push_back(joint);
    world_.push_back(world);
    return skeleton_.size() - 1;
  }
  const glm::vec3& world(const std::string& name) const { return world_[skeleton_.find(name)]; }
  int index(const std::string& name) const { return skeleton_.find(name); }
  Skeleton skeleton() const { return skeleton_; }

 private:
  Skeleton skeleton_;
  std::vector<glm::vec3> world_;
};

// A symmetric left/right side: sign +1 is the body's left (+X).
struct BodySide {
  float sign;
  std::string long_name;   // "Left" / "Right"
  std::string short_name;  // "L" / "R"
  int leg_chain, arm_chain, thumb_chain;
  glm::vec3 at(float x, float y, float z) const { return {sign * x, y, z}; }
  // Direction of the arm in the A-pose: outwards and 40 degrees down.
  glm::vec3 arm_direction() const {
    const float angle = kArmDropDegrees * std::numbers::pi_v<float> / 180.0f;
    return {sign * std::cos(angle), -std::sin(angle), 0.0f};
  }
  // Normal of the palm, towards the body and slightly down.
  glm::vec3 palm_normal() const { return sign * glm::cross(arm_direction(), kFront); }
};

PartSection section(float t, float side, float depth, float depth_offset = 0.0f) {
  return {t, side, depth, depth_offset};
}

BodyPart part(std::string name, int chain, glm::vec3 start, glm::vec3 end, glm::vec3 front,
              std::vector<PartSection> sections, float start_cap, float end_cap) {
  return {std::move(name), chain, start, end, front, std::move(sections), start_cap, end_cap};
}

void add_spine(SkeletonBuilder& joints, MannequinAnatomy& anatomy) {
  // One part from the hips to the chest, so the profile has no creases where parts would meet.
  // The profile ends at the broadest upper chest and a long cap domes it up to the shoulders:
  // a profile that narrowed to 1.42 m and ended there (flat, as every section list ends) bent
  // back to vertical just before its cap, a groove whose normals swung 35 degrees within 3 cm,
  // drawn as a ring across the chest at rest in every method (issue 17).
  const float bottom = 0.87f, top = 1.36f;
  auto at_height = [&](float y, float side, float depth, float depth_offset) {
    return section((y - bottom) / (top - bottom), side, depth, depth_offset);
  };
  anatomy.parts.push_back(part(
      "torso", kSpineChain, {0.0f, bottom, -0.015f}, {0.0f, top, -0.0195f}, kFront,
      {at_height(0.87f, 0.150f, 0.105f, -0.005f),  // buttocks
       at_height(0.93f, 0.168f, 0.115f, -0.010f),  // hips
       at_height(1.01f, 0.150f, 0.105f, -0.005f),
       at_height(1.08f, 0.137f, 0.100f, 0.000f),                                            // waist
       at_height(1.17f, 0.143f, 0.105f, 0.005f), at_height(1.25f, 0.160f, 0.116f, 0.012f),  // chest
       at_height(1.36f, 0.165f, 0.113f, 0.010f)},  // shoulders: the cap's base
      0.07f, 0.12f));
  // The neck's lower end and the shoulders' inner ends lie inside the torso. Closed by 2 cm caps
  // they met the torso's top in blunt fillets, whose smooth-minimum band edges dotted the ring
  // across the upper chest (with the domed torso alone the ring's rows still measured 1.7x the
  // lower chest at 20k, 2.2x at 72k: mannequin_test); 5 cm caps taper them into the dome.
  anatomy.parts.push_back(part(
      "neck", kSpineChain, {0.0f, 1.44f, -0.035f}, {0.0f, 1.63f, -0.01f}, kFront,
      {section(0.0f, 0.065f, 0.060f), section(0.4f, 0.054f, 0.055f), section(1.0f, 0.050f, 0.052f)},
      0.05f, 0.02f));
  anatomy.parts.push_back(
      part("head", kSpineChain, {0.0f, 1.595f, 0.0f}, {0.0f, 1.70f, 0.0f}, kFront,
           {section(0.0f, 0.062f, 0.078f, 0.010f), section(0.6f, 0.077f, 0.097f, 0.005f),
            section(1.0f, 0.072f, 0.092f)},
           0.05f, 0.055f));

  const char* names[] = {"LowerBack", "Spine", "Spine1", "Neck", "Neck1", "Head"};
  const glm::vec3 positions[] = {{0.0f, 1.06f, -0.03f},  {0.0f, 1.18f, -0.035f},
                                 {0.0f, 1.31f, -0.04f},  {0.0f, 1.50f, -0.045f},
                                 {0.0f, 1.55f, -0.035f}, {0.0f, 1.60f, -0.025f}};
  const float blend[] = {0.05f, 0.05f, 0.06f, 0.025f, 0.025f, 0.03f};
  SkinChain chain;
  chain.bones.push_back({joints.index("Hips"), {0.0f, 0.82f, -0.01f}, positions[0], 0.0f});
  std::string parent = "Hips";
  for (int i = 0; i < 6; ++i) {
    const int joint = joints.add(names[i], parent, positions[i]);
    const glm::vec3 end = i + 1 < 6 ? positions[i + 1] : glm::vec3(0.0f, 1.75f, -0.02f);
    chain.bones.push_back({joint, positions[i], end, blend[i]});
    parent = names[i];
  }
  anatomy.chains[kSpineChain] = chain;
}

void add_leg(const BodySide& side, SkeletonBuilder& joints, MannequinAnatomy& anatomy) {
  const std::string& n = side.long_name;
  const glm::vec3 hips = joints.world("Hips");
  joints.add(side.short_name + "HipJoint", "Hips", hips);
  const glm::vec3 up_leg = side.at(0.095f, 0.92f, 0.0f);
  const glm::vec3 knee = side.at(0.105f, 0.50f, 0.01f);
  const glm::vec3 ankle = side.at(0.115f, 0.085f, -0.025f);
  const glm::vec3 toe_base = side.at(0.12f, 0.025f, 0.115f);
  const glm::vec3 toe_tip = side.at(0.12f, 0.02f, 0.18f);
  const int up_leg_joint = joints.add(n + "UpLeg", side.short_name + "HipJoint", up_leg);
  const int leg_joint = joints.add(n + "Leg", n + "UpLeg", knee);
  const int foot_joint = joints.add(n + "Foot", n + "Leg", ankle);
  const int toe_joint = joints.add(n + "ToeBase", n + "Foot", toe_base);

  anatomy.chains[side.leg_chain].bones = {{joints.index("Hips"), hips, up_leg, 0.0f},
                                          {up_leg_joint, up_leg, knee, 0.07f},
                                          {leg_joint, knee, ankle, 0.05f},
                                          {foot_joint, ankle, toe_base, 0.04f},
                                          {toe_joint, toe_base, toe_tip, 0.02f}};
  // One part from hip to ankle (the knee is within 1.5 cm of that line): no crease at the knee.
  const float thigh = glm::length(knee - up_leg), shin = glm::length(ankle - knee);
  auto on_thigh = [&](float f) { return f * thigh / (thigh + shin); };
  auto on_shin = [&](float f) { return (thigh + f * shin) / (thigh + shin); };
  anatomy.parts.push_back(part(
      n + " leg", side.leg_chain, up_leg, ankle, kFront,
      {section(on_thigh(0.0f), 0.082f, 0.085f),
       section(on_thigh(0.3f), 0.075f, 0.080f, 0.005f),  // quadriceps
       section(on_thigh(0.75f), 0.058f, 0.062f), section(on_shin(0.0f), 0.050f, 0.053f),  // knee
       section(on_shin(0.3f), 0.054f, 0.057f, -0.012f),                                   // calf
       section(on_shin(0.75f), 0.036f, 0.038f), section(on_shin(1.0f), 0.032f, 0.034f)},  // ankle
      0.05f, 0.03f));
  // The foot's depth axis is vertical: its sole sits on y = 0 from heel to toes.
  anatomy.parts.push_back(part(n + " foot", side.leg_chain, side.at(0.115f, 0.045f, -0.06f),
                               side.at(0.12f, 0.027f, 0.16f), kUp,
                               {section(0.0f, 0.035f, 0.045f), section(0.4f, 0.042f, 0.040f),
                                section(0.75f, 0.048f, 0.028f), section(1.0f, 0.045f, 0.024f)},
                               0.02f, 0.035f));
}

void add_arm(const BodySide& side, SkeletonBuilder& joints, MannequinAnatomy& anatomy) {
  const std::string& n = side.long_name;
  const glm::vec3 d = side.arm_direction();
  const glm::vec3 palm = side.palm_normal();
  const glm::vec3 clavicle = side.at(0.025f, 1.44f, -0.045f);
  // The shoulder joint sits far enough out that the arm hangs beside the chest, not in it
  // (20 cm from the midline beside a 16.5 cm half-chest and a 5 cm upper arm: 50 cm across the
  // deltoids, about an adult man's), and low enough that the shoulders slope down from the
  // neck. At 17.5 cm and 1.435 m the hanging arm went 4 cm into the chest, which every method
  // drew as skin through skin, and the shoulders stood level with the chin: epaulettes with the
  // arms down (issue 17).
  const glm::vec3 shoulder = side.at(0.20f, 1.40f, -0.05f);
  const glm::vec3 elbow = shoulder + 0.29f * d;  // upper arm 29 cm, forearm 25 cm
  const glm::vec3 wrist = elbow + 0.25f * d;
  const glm::vec3 knuckles = wrist + 0.095f * d;
  const glm::vec3 finger = knuckles + 0.045f * d;
  const glm::vec3 finger_tip = finger + 0.05f * d;
  const glm::vec3 thumb = wrist + 0.02f * d + 0.025f * kFront + 0.005f * palm;
  const glm::vec3 thumb_tip =
      thumb + 0.06f * glm::normalize(0.55f * d + 0.75f * kFront + 0.35f * palm);

  const int shoulder_joint = joints.add(n + "Shoulder", "Spine1", clavicle);
  const int arm_joint = joints.add(n + "Arm", n + "Shoulder", shoulder);
  const int fore_arm_joint = joints.add(n + "ForeArm", n + "Arm", elbow);
  const int hand_joint = joints.add(n + "Hand", n + "ForeArm", wrist);
  const int finger_base_joint = joints.add(n + "FingerBase", n + "Hand", knuckles);
  const int finger_joint = joints.add(n + "HandFinger1", n + "FingerBase", finger);
  const int thumb_joint = joints.add(side.short_name + "Thumb", n + "Hand", thumb);

  anatomy.chains[side.arm_chain].bones = {
      {joints.index("Spine1"), {0.0f, 1.38f, -0.04f}, clavicle, 0.0f},
      {shoulder_joint, clavicle, shoulder, 0.03f},
      {arm_joint, shoulder, elbow, 0.05f},
      {fore_arm_joint, elbow, wrist, 0.045f},
      {hand_joint, wrist, knuckles, 0.035f},
      {finger_base_joint, knuckles, finger, 0.025f},
      {finger_joint, finger, finger_tip, 0.02f}};
  anatomy.chains[side.thumb_chain].bones = {{hand_joint, wrist, thumb, 0.0f},
                                            {thumb_joint, thumb, thumb_tip, 0.015f}};

  anatomy.parts.push_back(
      part(n + " shoulder", side.arm_chain, clavicle + side.at(0.005f, -0.01f, 0.0f),
           shoulder - 0.005f * d, kFront,
           // Flatter towards the joint (4 cm high where the arm's root is 4.2 cm above it) so
           // that its end does not stand above the arm as a knob.
           {section(0.0f, 0.048f, 0.050f), section(1.0f, 0.040f, 0.052f)}, 0.05f,
           0.03f));  // the inner cap: see the neck's
  // One part from shoulder to wrist (straight in the A-pose): no crease at the elbow.
  auto on_upper_arm = [](float f) { return f * 0.29f / 0.54f; };
  auto on_forearm = [](float f) { return (0.29f + f * 0.25f) / 0.54f; };
  anatomy.parts.push_back(
      part(n + " arm", side.arm_chain, shoulder, wrist, kFront,
           {section(on_upper_arm(0.0f), 0.052f, 0.055f),  // deltoid
            section(on_upper_arm(0.2f), 0.048f, 0.050f),
            section(on_upper_arm(0.55f), 0.041f, 0.046f, 0.004f),  // biceps
            section(on_upper_arm(0.9f), 0.036f, 0.038f),
            section(on_forearm(0.0f), 0.035f, 0.037f),  // elbow
            section(on_forearm(0.25f), 0.039f, 0.043f), section(on_forearm(0.7f), 0.030f, 0.032f),
            section(on_forearm(1.0f), 0.021f, 0.028f)},  // wrist
           0.03f, 0.015f));
  // Hands: `side` is the palm's thickness, `depth` (towards +Z) its width.
  anatomy.parts.push_back(part(
      n + " hand", side.arm_chain, wrist, knuckles, kFront,
      {section(0.0f, 0.018f, 0.030f), section(0.5f, 0.019f, 0.043f), section(1.0f, 0.015f, 0.044f)},
      0.015f, 0.01f));
  anatomy.parts.push_back(part(
      n + " fingers", side.arm_chain, knuckles, finger_tip, kFront,
      {section(0.0f, 0.013f, 0.042f), section(0.6f, 0.011f, 0.038f), section(1.0f, 0.009f, 0.030f)},
      0.01f, 0.02f));
  anatomy.parts.push_back(part(n + " thumb", side.thumb_chain, thumb - 0.01f * d, thumb_tip, d,
                               {section(0.0f, 0.013f, 0.014f), section(1.0f, 0.010f, 0.011f)},
                               0.012f, 0.012f));
}

}  // namespace

MannequinAnatomy make_mannequin_anatomy() {
  MannequinAnatomy anatomy;
  anatomy.chains.resize(7);
  SkeletonBuilder joints;
  const BodySide left{1.0f, "Left", "L", kLeftLeg, kLeftArm, kLeftThumb};
  const BodySide right{-1.0f, "Right", "R", kRightLeg, kRightArm, kRightThumb};
  // Joint order follows the CMU BVH files: legs, then spine and head, then arms.
  joints.add("Hips", "", {0.0f, 0.97f, -0.01f});
  add_leg(left, joints, anatomy);
  add_leg(right, joints, anatomy);
  add_spine(joints, anatomy);
  add_arm(left, joints, anatomy);
  add_arm(right, joints, anatomy);
  anatomy.skeleton = joints.skeleton();
  return anatomy;
}

}  // namespace sweepd::mannequin
