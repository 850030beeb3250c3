// Foot planting: a retargeted clip's feet put on the model's floor where the clip plants them.
//
// Rotations retargeted bone by bone (motion/retarget.h) land the clip's feet where the model's
// proportions put them: the male's soles sank up to 5 cm below the floor in CMU's walks (before
// retarget.h took the clip's hip height as it stands), since its legs, ankles and feet are not
// the clip's, and no root scale makes every frame agree. Production retargeters correct this with
// leg IK on the frames where a foot is planted, holding the planted foot still (MotionBuilder's
// floor contact, Unreal's IK retargeter); so does this.
//
// Definitions (the model in metres, Y up; L its hip height on straight legs, about 0.9 m):
//   sole     the rest mesh's vertices at or below the ankle whose strongest influence is the
//            foot's joint or a joint below it (toes), each carried rigidly by that joint; its
//            height is its lowest point's, above the floor (the rest mesh's lowest vertex).
//   settle   a body the retargeting floats (its legs, ankles and feet are not the clip's: the
//            20k mannequin's soles stood 2.5-5.7 cm up in cmu_01_01) comes down on every frame
//            by its lower foot's stance, the 2nd percentile of that foot's heights over the
//            clip, when that lies between 0 and 0.1 L (a clip whose feet stay higher, sitting
//            or hanging, has no floor to come down to).
//   contact  a clip frame where a foot is planted, found on the retargeted clip: the sole
//            within 0.07 L of the floor once the body has come down (or below it), and the
//            sole's lowest point (that point of the foot, not the lowest of other frames, which
//            jumps between heel and toes as the foot rolls and can stand still under a foot
//            that swings) moving under 0.4 L per second, in three dimensions (a foot coming
//            down to land is not planted yet), over 0.05 s each side (a landing foot's marker
//            noise jitters it 2-3 cm between 120 Hz frames in cmu_01_03). A standing foot's
//            roll and noise stay under both; a foot lifted for the next step passes them
//            within a frame or two. The window is wider than a viewer's (tests/motion/
//            foot_tracks.h: 5 cm and 0.25 m/s), so what a viewer calls planted is planted.
//            A contact broken for no longer than the speed window's 0.1 s, the sole within
//            the contact height throughout, goes on through the break (one noisy frame makes
//            the window fast for that long).
// Steadied feet: a planted foot's world rotation is the clip's with its noise taken out (in
// cmu_01_03 frames 400-424 the clip's planted foot turns 5-20 degrees a frame and back, and a
// held ankle under a bent leg turned that into knee steps several times the clip's): on each
// contact frame, a line fitted by weighted least squares to the contact's own rotations about
// the frame (as turns from the frame's; Gaussian weights of deviation 0.05 s, to 3 deviations,
// the foot landing or peeling off not included), taken at the frame; the turn from the clip's
// rotation fades out as offsets do (below). The soles are then measured again on the steadied
// feet and the contacts found first kept, more found (so a foot is turned only within 0.15 s
// of its contacts, or across a short gap between two).
// Straightest planted leg: on a contact frame a leg reaches no further than the clip's own leg
// (its hip-to-ankle distance), and no less than kSoftReach short of its length (a nearly
// straight knee under a held ankle moves several times as far as the hip: a model straightening
// a knee the clip bends 23 degrees stepped it 5 cm in a frame), and at least 0.1 % short of it
// (the knee bent about 5 degrees: at a straight knee float round-off moves the knee).
// On a contact frame the ankle moves up or down by the sole's height, so the sole touches the
// floor, and across so that the sole does not slide: the foot keeps its (steadied) world
// orientation (heel-to-toe roll is the clip's), and each frame's ankle is shifted so that the
// point of the sole lowest at the frame before (with the points within 0.01 mm of it: a flat
// foot's ties) stands where it stood then (a foot rolling on that point
// keeps it still; the clip's own point drifts: cmu_01_03's contacts on the male move it 5.8 cm
// net on average, 15 cm at most, and jitter up to 3.5 cm in a frame, so that summed frame by
// frame it travelled 35 cm a contact on average and 84 cm at most). Each contact's
// shifts less their mean, so the ankle stands where the clip's does on average over the
// contact and footfalls keep their places. The hip stays; the knee bends or straightens in its own
// plane and the thigh swings (two-bone IK). Where a straightened leg cannot reach the floor at the
// shifted ankle, the whole body comes down as far as that foot needs, eased in and out over
// 0.15 s around the frame (so it never drops faster than its deepest need per 0.15 s);
// dropping it may bring a slow foot into contact, so contacts are found again until none is
// added. Between contacts a foot's offset fades linearly to zero within 0.15 s of each, or,
// across a gap shorter than 0.3 s, goes linearly from one contact's to the next's, so nothing
// pops; across, a contact's shift first holds while the sole stays within the contact height
// after or before it (a foot peeling off or landing moves as the clip's does), unless the sole
// stays that low through the whole gap, or the two holds would leave less than 0.15 s between
// them. On no frame does a sole go below the floor. An ankle
// that cannot reach its target moves towards it as far as the leg reaches (two_bone_ik.h):
// exactly on a contact frame (the body comes down so that it reaches, above), and with a soft
// reach (kSoftReach) from 0.15 s away from the foot's contacts, eased linearly between, so that
// a leg straightening as its target goes out of reach does not snap its knee (a fading shift
// along a leg stretched on the floor stepped the knee by up to 13 cm in a frame).
// Parts the clip rests on its floor other than the feet (a kneeling knee, motion/
// clip_resting_knees.h) may ask the body to come down further (`lowered`, per clip frame: the
// least drop from the uncorrected pose), eased in and out as a foot's need is; the planted legs'
// IK takes it up as it takes up any drop.
// A clip sampled between frames (pose_at_time) puts the sole on the floor exactly where both
// frames are contact frames and interpolates the frames' offsets (across everywhere) and the
// body's drop.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <utility>
#include <vector>

#include "deform/model/model.h"
#include "deform/model/pose.h"
#include "deform/rig/rig_map.h"

namespace sweepd::motion {

class FootPlanting {
 public:
  // nullopt when no foot can be planted: no leg with its hip, knee and ankle joints in the
  // model's rig map, or no sole vertices (a bare skeleton).
  //   frame_pose  the retargeted, uncorrected pose of clip frame f, for 0 <= f < frame_count
  //   frame_time  seconds between clip frames
  //   hip_height  the model's pelvis height above its floor on straight legs (L above)
  //   lowered     per clip frame, the least drop of the body (see the header), or empty
  static std::optional<FootPlanting> build(const deform::Model& model, const deform::RigMap& map,
                                           float hip_height, int frame_count, double frame_time,
                                           const std::function<deform::Pose(int)>& frame_pose,
                                           const std::vector<float>& lowered = {});

  // How far the body comes down on clip frame `frame` (m).
  float drop(int frame) const { return hip_drop_.at(frame); }

  // Corrects `pose`, the uncorrected pose of the clip at `seconds` (clamped to the clip).
  void apply(double seconds, deform::Pose& pose) const;

  // Whether the foot of `side` (0 the rig map's left leg, 1 its right) is in contact on clip
  // frame `frame`.
  bool planted(int side, int frame) const;

  // Foot sliding, per contact (a run of contact frames of one foot): the horizontal path of the
  // sole's contact point, summed over each pair of consecutive frames as the move of the point
  // lowest at the first of them (a foot that rolls from heel to toe without slipping moves its
  // contact point by almost nothing; one that skates moves it by the skate).
  // frame_pose: the clip's corrected pose of frame f (Retargeter::pose_at_frame).
  struct ContactSlide {
    int side = 0;             // 0 the rig map's left leg, 1 its right
    int first = 0, last = 0;  // clip frames
    float slide = 0.0f;       // m
  };
  std::vector<ContactSlide> contact_slides(
      const std::function<deform::Pose(int)>& frame_pose) const;

 private:
  struct SolePoint {
    int joint;
    glm::vec4 local;  // the rest position in the joint's rest frame
  };
  struct Foot {
    deform::LegJoints leg;
    std::vector<SolePoint> sole;
    glm::vec4 centre;                   // the sole's centroid in the foot's rest frame
    std::vector<glm::vec3> offset;      // the ankle's move, per clip frame
    std::vector<std::uint8_t> contact;  // per clip frame
    std::vector<float> softness;        // the leg IK's, per clip frame (see the header)
    std::vector<glm::vec3> steadying;   // per clip frame: the foot's world turn, axis * angle
    int side = 0;                       // 0 the rig map's left leg, 1 its right
  };
  struct Sole {
    float height;        // above the floor
    std::size_t lowest;  // its lowest point, an index into Foot::sole
    float speed;         // that point's speed
    glm::vec2 step;      // that point's horizontal move to the next clip frame (x, z)
    glm::vec3 to_ankle;  // from the hip joint to the ankle
    float leg;           // thigh and shin
  };

  FootPlanting(const deform::Model& model, float floor, double frame_time);
  // Every clip frame's soles (and, where foot_rotation is given, each foot's world rotation).
  std::vector<std::vector<Sole>> measure_soles(
      const std::function<deform::Pose(int)>& frame_pose,
      std::vector<std::vector<glm::quat>>* foot_rotation) const;
  // Each foot's steadying turns from the contacts found and its world rotation per frame (see
  // the header); whether any foot turns.
  bool steady_feet(const std::vector<std::vector<glm::quat>>& foot_rotation);
  // Turns each foot of `pose`, clip frames f0 and f1 mixed by alpha, by its steadying.
  void steady(int f0, int f1, float alpha, deform::Pose& pose) const;
  Sole sole_of(const Foot& foot, const std::vector<glm::mat4>& world) const;
  // Where the uncorrected foot stands over the clip, above the model's floor (see the header).
  static float stance(const std::vector<Sole>& soles);
  // How far the hip must come down for the leg, straightened, to put the sole on the floor with
  // the ankle moved across by `shift` (x, z).
  static float hip_drop(const Sole& sole, glm::vec2 shift);
  // Contacts, the pelvis's drop and the feet's offsets (across and up) from the uncorrected soles
  // per frame; keep_contacts: the feet's contacts so far stay, and more are found.
  void plan(const std::vector<std::vector<Sole>>& soles, float hip_height,
            bool keep_contacts = false);
  // Fills the frames not `known` from the known ones: a fade or a bridge (see the header).
  void spread(std::vector<glm::vec3>& values, const std::vector<std::uint8_t>& known) const;
  // The horizontal shifts that hold each contact's sole still (see the header) into foot.offset.
  void pin(Foot& foot, const std::vector<Sole>& soles) const;
  // Per clip frame: no softness on a contact frame, kSoftReach from kFade away, linear between.
  void soften(Foot& foot) const;
  void move_ankle(const Foot& foot, glm::vec3 shift, float softness,
                  const std::vector<glm::mat4>& world, const std::vector<glm::quat>& rotation,
                  deform::Pose& pose) const;

  deform::Skeleton skeleton_;
  std::vector<glm::mat4> rest_inverse_;
  float floor_ = 0.0f;
  double frame_time_ = 0.0;
  int frame_count_ = 0;
  std::vector<Foot> feet_;       // at most two
  std::vector<float> hip_drop_;  // per clip frame: the root's move down
  std::vector<float> lowered_;   // per clip frame: the least drop asked for, or empty
};

}  // namespace sweepd::motion
