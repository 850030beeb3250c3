// Body contacts: the parts of a retargeted body other than the feet that rest on the floor
// (knees, hips and seat, hands, back) held still while they rest there (issue 48 item 3).
//
// Foot planting (foot_planting.h) holds the feet; the body floor (body_floor.h) lifts the body
// so that no part goes below the floor. A part that lies on the floor then still moved across
// it as the clip's root and limbs moved: a knocked-down body skated on its back and seat.
//
// Parts (per joint, from the rig map, deform::label_joints): back (the torso above the pelvis,
// neck, head), hips (the pelvis, hip links and thighs: seat and buttocks), each knee (the shin
// and knee, below the rig map's knee joint down to the ankle), each hand (the wrist and below),
// each arm (clavicle, upper arm, forearm: elbows). The feet are foot planting's, and so is
// what lies at or below the ankle at rest or is moved by the foot's joint at all (the skin
// blended across the ankle: lying beside a planted sole it rolls with the foot, and holding
// it as a knee would fight the foot's roll).
// Definitions (the model in metres, Y up; L its hip height on straight legs, about 0.9 m):
//   lowest   a part's lowest point on a frame: the lowest of its body samples (body_samples.h,
//            the body floor's, skinned by linear blending), above the floor.
//   contact  a clip frame where a part rests on the floor: its lowest point within 0.035 L of
//            the floor (3 cm on a 0.9 m hip; a part lifted by the body floor rests 0.5 cm up)
//            and that point of the part moving under 0.4 L per second in three dimensions,
//            over 0.05 s each side, as a foot's contact (foot_planting.h), on the pose with the
//            feet planted and the body lifted. A break no longer than 0.1 s with the part down
//            throughout is bridged. A part the clip moves across the floor faster is sliding as
//            the clip means it to (a slide, a roll that slips, a body pushed along), and does.
//   slide    per contact, the horizontal path of the part's contact point, summed over each
//            pair of consecutive frames as the move of the point lowest at the first of them
//            (as foot planting's: a part that rolls without slipping moves it by almost
//            nothing).
// Holding (each hold is a horizontal shift per clip frame: in a run of contact frames it goes
// on by the opposite of the contact point's step, so the point stands where it touched down;
// after a run it fades linearly to zero within max(0.15 s, shift / 0.25 L per second), and a
// new run starts from what is left of it, so nothing pops; a hold never moves faster than
// 0.8 L/s, twice a contact's speed, whatever one frame's step, and fades at 0.25 L/s):
//   root     the back and hips move with the root: the root is shifted across (never up or
//            down) by the mean step of the back's and hips' contact points where either rests
//            (where both rest and turn against each other, the root follows their mean and
//            each keeps what is left). A knee resting within 0.15 s of its foot's planting
//            (kneeling: the ankle is foot planting's, so the leg has no freedom left but the
//            hip's) moves with the root too, and wins over the back and hips: the root follows
//            the mean step of such knees' joints on the clip's own legs (the poses before foot
//            planting: the hip keeps the place the clip gives it relative to the knee, and the
//            ankle stands, so the whole leg stands; a thigh resting beside that knee, which the
//            hips part holds, goes with it). Where none of these rests but two or more limbs
//            do (all fours), by the mean of the limbs' contact points ("several contacts
//            agree"; one limb alone is held by its IK).
//   knees    the thigh swings about the hip so that the knee moves across, keeping its height;
//            the shin keeps its world rotation, but the knee never folds past the clip's bend
//            (two_bone_ik.h, move_limb_middle: a swept joint folded further bulged below the
//            samples the body floor lifts by). Not while
//            that side's foot is planted: the feet win (the leg is foot planting's, and the
//            root holds the knee); the knee's shift tapers linearly to nothing over the 0.15 s
//            before and after.
//   arms     the same with the upper arm about the shoulder (an elbow or forearm resting).
//   hands    the arm's two-bone IK moves the wrist across to where the hand's hold puts it
//            (from where the elbow's hold left it);
//            the hand keeps its world rotation. The hands win over the elbows.
//   raised   an arm the body floor raises off the floor (body_floor.h: the clip pushes it
//   arms     through its own beside its lying torso) moves with the raise, so the holds above,
//            measured before it, left it sliding as the clip swung it (2.5-30.7 cm a contact
//            knocked down forwards). A contact of such an arm (touching a frame the floor
//            raises it on) during which its hand never rests is held after the raise instead:
//            its shift is measured on the raised poses, the elbow swung across so that the
//            arm's lowest point stands where its hold puts it, the arm raised again where that
//            dipped it and the point moved across again (a raise about the shoulder moves it),
//            three times; the shift tapers to nothing within 0.15 s of a resting hand and of
//            a frame where the floor does not raise the arm (the lift is built without this
//            hold, so only the raise keeps the held arm off the floor: the RiggedFigure
//            without its spine joint, knocked down backwards, went 3.7 cm below it). Where
//            the hand rests too, the hand's hold before the lift keeps the hand (the raise lifts
//            its wrist straight up): held after the raise as well, the elbow dragged the held
//            hand along (the male's 0.1 -> 4.2 cm).
// Order: the root hold is applied before foot planting, and foot planting is built again on
// the held root (a planted foot stays planted: the legs' IK takes up the root's shift); what
// the back and hips still slide then (planting turns the thighs otherwise on a held root),
// and what the knees beside planted feet still move on the clip's own legs, is added to the
// hold (refine_root), four times over, planting again each time; the limbs' holds come
// after foot planting; the body floor is then built again over every hold, so no hold
// pushes a part below the floor (a swung thigh or a bent elbow can dip the skin); the raised
// arms' holds are planned last, on the lifted and raised poses, and applied after the lift.
// Conflicts: the feet win over everything (above); the root hold wins over the clip's path
// where the back or hips rest (the body stays where it lay down), and a knee beside its
// planted foot wins over the back and hips (above); the clip wins where it moves
// a resting part faster than a contact (see contact), and the hold then fades at 0.25 L/s. The
// body floor's lift (vertical) wins over every hold: no part goes lower than it allows.
// Inputs:  the model's skeleton, its rig map, L, the body floor built over the clip with
//          part_of_samples() as its groups, the clip's frame count and time, frame_pose (each
//          clip frame's pose as the body floor saw it, lifted).
// Outputs: hold_root() (the root's shift, applied before foot planting), hold_limbs() (the
//          limbs' IK, applied after foot planting and before the body floor's lift, which is
//          built again over them), hold_raised_arms() (after the lift and the arms' raise),
//          contact_slides() (measured on any poses of the clip).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "deform/model/model.h"
#include "deform/model/pose.h"
#include "deform/rig/rig_map.h"
#include "motion/body_floor.h"
#include "motion/two_bone_ik.h"

namespace sweepd::motion {

class BodyContacts {
 public:
  enum Part : int {
    kBack,
    kHips,
    kLeftKnee,
    kRightKnee,
    kLeftHand,
    kRightHand,
    kLeftArm,
    kRightArm,
  };
  static constexpr int kPartCount = 8;
  // A part rests within this share of the hip height above the floor (see contact above).
  static constexpr float kPartContactHeight = 0.035f;
  static const char* name(int part);  // "back", "hips", "left knee", ...

  // Per joint: its part, or -1 (the feet, joints above the pelvis).
  static std::vector<int> part_of_joints(const deform::RigMap& map,
                                         const deform::Skeleton& skeleton);

  // Per body sample (body_samples.h): its part, or -1; a knee's samples are those above its
  // ankle at rest (a shin joint may carry the foot's skin) that the foot's joint (or one below
  // it) does not move. The body floor's groups.
  static std::vector<int> part_of_samples(const deform::RigMap& map,
                                          const deform::Skeleton& skeleton,
                                          const BodySamples& samples);

  // foot_planted(side, frame): whether foot planting holds that foot (on the poses that
  // frame_pose gives; a knee resting near it is the root's), or empty; clip_legs_pose: each
  // clip frame's pose before foot planting (the root held as frame_pose's is), on which such
  // a knee's joint is held, or empty (then frame_pose's).
  static BodyContacts find(const deform::Skeleton& skeleton, const deform::RigMap& map,
                           float hip_height, const BodyFloor& body_floor, int frame_count,
                           double frame_time, const std::function<deform::Pose(int)>& frame_pose,
                           const std::function<bool(int, int)>& foot_planted = {},
                           const std::function<deform::Pose(int)>& clip_legs_pose = {});

  // Whether any part rests on the floor on any frame.
  bool any() const;
  // Whether any back or hips contact moves the root.
  bool holds_root() const { return holds_root_; }
  // Shifts `pose`'s root across by the root hold at `seconds` (clamped to the clip).
  void hold_root(double seconds, deform::Pose& pose) const;
  // Adds to the root hold what the back and hips or the limbs still slide on frame_pose (the
  // clip's poses with this hold, the feet planted again on it: planting turns the thighs
  // otherwise on a held root), and what the joints of the knees beside planted feet still
  // move on clip_legs_pose (as find's, with this hold).
  void refine_root(const std::function<deform::Pose(int)>& frame_pose,
                   const std::function<deform::Pose(int)>& clip_legs_pose);
  // The limbs' holds (knees, arms, hands): their shifts measured on frame_pose (the clip's
  // poses with the root held and the feet planted), over the contacts found;
  // foot_planted(side, frame): whether foot planting holds that foot (its knee is then not
  // held); raised(side, frame): whether the body floor raises that arm on the frame (an arm's
  // contact that touches such a frame is left to plan_raised_arms, see raised_runs), or empty.
  void plan_limbs(const std::function<deform::Pose(int)>& frame_pose,
                  const std::function<bool(int, int)>& foot_planted,
                  const std::function<bool(int, int)>& raised = {});
  void hold_limbs(double seconds, deform::Pose& pose) const;
  // The holds of the arms the body floor raises (raised as plan_limbs'), over the contacts
  // raised_runs gives: their shifts measured on frame_pose (the clip's poses with every other
  // hold, lifted and the arms raised), applied after the raise (hold_raised_arms).
  void plan_raised_arms(const std::function<deform::Pose(int)>& frame_pose,
                        const std::function<bool(int, int)>& raised);
  // Moves each raised arm's lowest point across to where its hold puts it (the elbow swung
  // across, move_limb_middle), and has body_floor raise the arm again where that dipped it,
  // kRaisedHoldPasses times (a raise that swings the arm up about its shoulder moves that
  // point across again).
  void hold_raised_arms(double seconds, const BodyFloor& body_floor, deform::Pose& pose) const;
  static constexpr int kRaisedHoldPasses = 3;

  struct ContactSlide {
    int part = 0;
    int first = 0, last = 0;  // clip frames
    float slide = 0.0f;       // m
  };
  // Slide per contact over the contacts found, measured on frame_pose.
  std::vector<ContactSlide> contact_slides(
      const std::function<deform::Pose(int)>& frame_pose) const;
  // Contact frames of a part (per clip frame, 1 in contact).
  const std::vector<std::uint8_t>& contact(int part) const { return parts_[part].contact; }

 private:
  struct PartTrack {
    std::vector<std::uint8_t> contact;  // per clip frame
    std::vector<int> samples;           // the part's, into samples_
  };
  BodyContacts(const deform::Skeleton& skeleton, double frame_time, int frame_count);
  // Per frame: the horizontal step of each part's contact point to the next frame, on
  // frame_pose, where the part is in contact on both (else nothing).
  std::vector<std::array<std::optional<glm::vec2>, kPartCount>> contact_steps(
      const std::function<deform::Pose(int)>& frame_pose, std::array<bool, kPartCount> which) const;
  // Per frame, per side: the horizontal step of the knee joint to the next frame, on
  // clip_legs_pose, where that knee is bound to its planted foot (knee_bound_) on the frame.
  std::vector<std::array<std::optional<glm::vec2>, 2>> knee_joint_steps(
      const std::function<deform::Pose(int)>& clip_legs_pose) const;
  // Holds from steps: anchored where a run of held frames starts, then faded or bridged.
  std::vector<glm::vec2> hold(const std::vector<std::uint8_t>& held,
                              const std::vector<glm::vec2>& step) const;
  glm::vec2 at(const std::vector<glm::vec2>& values, double seconds) const;
  // kFade in clip frames (at least one).
  int taper() const;
  // Per clip frame: how many frames from the nearest frame where that side's foot is planted
  // (or whatever foot_planted(side, frame) says), at most taper().
  std::vector<int> planted_distance(int side,
                                    const std::function<bool(int, int)>& foot_planted) const;
  // Whether a knee bound to its planted foot rests on `frame` (the root holds it).
  bool knee_bound(int frame) const;
  // Per clip frame, 1 within a contact of an arm part (kLeftArm, kRightArm) that touches a
  // frame where raised(side, frame) and during which that side's hand never rests; empty for
  // other parts or no raised.
  std::vector<std::uint8_t> raised_runs(int part,
                                        const std::function<bool(int, int)>& raised) const;
  // No hold moves faster than 0.8 L/s (twice a contact's speed): one frame's step of a contact
  // point may be marker noise far above its speed over the window.
  void limit_rate(std::vector<glm::vec2>& values) const;

  deform::Skeleton skeleton_;
  std::vector<glm::mat4> rest_inverse_;
  std::shared_ptr<const BodySamples> samples_;
  double frame_time_ = 0.0;
  int frame_count_ = 0;
  float hip_height_ = 0.0f;
  std::array<PartTrack, kPartCount> parts_;
  std::array<LimbJoints, 2> arms_, legs_;  // left, right: shoulder, elbow, wrist; hip, knee
  bool holds_root_ = false, holds_limbs_ = false;
  std::vector<glm::vec2> root_shift_;    // per clip frame (x, z)
  std::vector<std::uint8_t> root_held_;  // per clip frame: the root follows a contact
  // Per side (left, right), per clip frame: the knee rests within kFade of its foot's planting.
  std::array<std::vector<std::uint8_t>, 2> knee_bound_;
  // Per part (knees, hands, arms), per clip frame (x, z); empty where the part is not held.
  std::array<std::vector<glm::vec2>, kPartCount> limb_shift_;
  // The same for the arms the body floor raises (kLeftArm, kRightArm), applied after the raise.
  std::array<std::vector<glm::vec2>, kPartCount> raised_arm_shift_;
  bool holds_raised_arms_ = false;
};

}  // namespace sweepd::motion
